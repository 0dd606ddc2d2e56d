// The interactive viewer: a GLFW window with an OpenGL 3.3 core context, the World drawn by a
// Renderer, an orbit camera and the ImGui "Simulation" panel.
#include "app/viewer.hpp"

#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cstdio>
#include <optional>

#include "core/error.hpp"
#include "render/orbit_camera.hpp"
#include "render/render_error.hpp"
#include "render/renderer.hpp"
#include "render/screenshot.hpp"
#include "render/world_view.hpp"
#include "ui/simulation_panel.hpp"
#include "ui/simulation_session.hpp"

namespace weft {

namespace {

void report_glfw_error(int code, const char* description) {
  std::fprintf(stderr, "weft: GLFW error %d: %s\n", code, description);
}

// GLFW from init to terminate; the window and its context live inside.
class GlfwLibrary {
 public:
  GlfwLibrary() : ok_(glfwInit() == GLFW_TRUE) {}
  ~GlfwLibrary() {
    if (ok_) glfwTerminate();
  }
  GlfwLibrary(const GlfwLibrary&) = delete;
  GlfwLibrary& operator=(const GlfwLibrary&) = delete;
  bool ok() const { return ok_; }

 private:
  bool ok_;
};

class Window {
 public:
  Window(const ViewerOptions& options, const std::string& title) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);  // macOS needs it, elsewhere harmless
    glfwWindowHint(GLFW_SAMPLES, 4);
    // A screenshot run draws one frame off screen.
    glfwWindowHint(GLFW_VISIBLE, options.screenshot_path.empty() ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(options.width, options.height, title.c_str(), nullptr, nullptr);
  }
  ~Window() {
    if (window_ != nullptr) glfwDestroyWindow(window_);
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
  GLFWwindow* get() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

// Dear ImGui bound to the window, with no imgui.ini written anywhere.
class ImGuiLayer {
 public:
  explicit ImGuiLayer(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
  }
  ~ImGuiLayer() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  void begin_frame() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
  }
  void end_frame() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
};

// Mouse over the 3D view (not over ImGui): left drag orbits, right or middle drag pans, wheel zooms.
void handle_camera_input(OrbitCamera& camera, int framebuffer_height) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureMouse) return;
  const double dx = io.MouseDelta.x;
  const double dy = io.MouseDelta.y;
  // Mouse motion comes in window units; pan works in framebuffer pixels (they differ on high-DPI).
  const double pixels_per_unit = io.DisplayFramebufferScale.y > 0.0f ? io.DisplayFramebufferScale.y : 1.0;
  if (io.MouseDown[0]) {
    camera.orbit(dx, dy);
  } else if (io.MouseDown[1] || io.MouseDown[2]) {
    camera.pan(dx * pixels_per_unit, dy * pixels_per_unit, framebuffer_height);
  }
  if (io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
}

void handle_keys(SimulationSession& session) {
  if (ImGui::GetIO().WantCaptureKeyboard) return;
  if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false)) session.playing = !session.playing;
}

// Runs the window until it is closed, or draws one screenshot. Returns the exit code.
int run_window(GLFWwindow* window, SimulationSession& session, const ViewerOptions& options) {
  ImGuiLayer imgui(window);
  Renderer renderer(WEFT_SHADER_DIR);
  WorldMeshes meshes = show_world(renderer, session.world());
  int shown_generation = session.generation();

  int framebuffer_width = 0, framebuffer_height = 0;
  glfwGetFramebufferSize(window, &framebuffer_width, &framebuffer_height);
  OrbitCamera camera;
  camera.frame(world_bounds(session.world()),
               framebuffer_height > 0 ? static_cast<double>(framebuffer_width) / framebuffer_height : 1.0);

  // Screenshot: a fixed number of frames, independent of wall time, then one picture.
  const bool screenshot = !options.screenshot_path.empty();
  if (screenshot) {
    for (int frame = 0; frame < options.frames; ++frame) session.advance_frame();
  }

  while (screenshot || !glfwWindowShouldClose(window)) {
    glfwPollEvents();
    glfwGetFramebufferSize(window, &framebuffer_width, &framebuffer_height);

    imgui.begin_frame();
    draw_simulation_panel(session);
    handle_camera_input(camera, framebuffer_height);
    handle_keys(session);
    if (session.playing && !screenshot) session.advance_frame();

    // Views follow the world: re-register after a reset, else push new positions.
    if (session.generation() != shown_generation) {
      meshes = show_world(renderer, session.world());
      shown_generation = session.generation();
    } else {
      update_world(renderer, meshes, session.world());
    }
    renderer.draw(camera, framebuffer_width, framebuffer_height);

    // The screenshot shows the 3D view only; the panel is drawn after it is read.
    if (screenshot) {
      try {
        save_back_buffer_png(options.screenshot_path, framebuffer_width, framebuffer_height);
      } catch (const IoError& error) {
        std::fprintf(stderr, "weft: %s\n", error.what());
        return 4;
      }
    }
    imgui.end_frame();
    glfwSwapBuffers(window);
    if (screenshot) break;
  }
  return 0;
}

}  // namespace

int run_viewer(const ViewerOptions& options) {
  // The scene is checked before any window opens, so a bad file fails the same way everywhere.
  std::optional<SimulationSession> session;
  try {
    session.emplace(options.scene_path, options.overrides);
  } catch (const SceneError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 2;
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 2;
  }

  glfwSetErrorCallback(report_glfw_error);
  GlfwLibrary glfw;
  const char* no_window_message =
      "weft: cannot open a window (no display?); run headless instead: weft --headless SCENE --out DIR\n";
  if (!glfw.ok()) {
    std::fputs(no_window_message, stderr);
    return 1;
  }
  Window window(options, "Weft - " + options.scene_path);
  if (window.get() == nullptr) {
    std::fputs(no_window_message, stderr);
    return 1;
  }
  glfwMakeContextCurrent(window.get());
  glfwSwapInterval(options.screenshot_path.empty() ? 1 : 0);
  if (gladLoadGL(glfwGetProcAddress) == 0) {
    std::fputs("weft: cannot load OpenGL 3.3 core functions\n", stderr);
    return 1;
  }

  try {
    return run_window(window.get(), *session, options);
  } catch (const RenderError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 1;
  }
}

}  // namespace weft
