// The interactive viewer: a GLFW window with an OpenGL 3.3 core context, the World drawn by a
// Renderer with its debug overlay, an orbit camera, mouse dragging of cloth vertices and the ImGui
// panels. The simulation steps on a thread of its own (ui/simulation_worker.hpp); the window draws
// the last finished step, so it stays responsive whatever a step costs.
#include "app/viewer.hpp"

#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "app/frame_times.hpp"
#include "app/progress.hpp"
#include "app/world_tangles.hpp"
#include "core/error.hpp"
#include "io/install_paths.hpp"
#include "io/recording_reader.hpp"
#include "render/orbit_camera.hpp"
#include "render/picking.hpp"
#include "render/render_error.hpp"
#include "render/renderer.hpp"
#include "render/screenshot.hpp"
#include "render/world_view.hpp"
#include "ui/panels.hpp"
#include "ui/recording_player.hpp"
#include "ui/simulation_session.hpp"
#include "ui/simulation_worker.hpp"
#include "ui/vertex_drag.hpp"
#include "ui/viewer_state.hpp"

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
    glfwWindowHint(GLFW_SAMPLES, 4);                        // MSAA
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);       // high-DPI: window size in logical units
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
    // Opaque panels: the dark style's translucent ones showed another panel's text through them.
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;
    // Thin, translucent slider handles: the value under them stays readable.
    ImGui::GetStyle().GrabMinSize = 5.0f;
    ImGui::GetStyle().Colors[ImGuiCol_SliderGrab].w = 0.45f;
    ImGui::GetStyle().Colors[ImGuiCol_SliderGrabActive].w = 0.7f;
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

// The window's sizes this frame: framebuffer pixels and window units differ on high-DPI screens.
struct Viewport {
  int framebuffer_width = 0, framebuffer_height = 0;
  int window_width = 0, window_height = 0;
  double aspect() const {
    return framebuffer_height > 0 ? static_cast<double>(framebuffer_width) / framebuffer_height : 1.0;
  }
  float pixel_scale() const {
    return window_width > 0 ? static_cast<float>(framebuffer_width) / window_width : 1.0f;
  }
};

// The camera ray under the mouse cursor.
Ray mouse_ray(const OrbitCamera& camera, const Viewport& viewport) {
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const double ndc_x = 2.0 * mouse.x / std::max(viewport.window_width, 1) - 1.0;
  const double ndc_y = 1.0 - 2.0 * mouse.y / std::max(viewport.window_height, 1);
  return camera_ray(camera, viewport.aspect(), ndc_x, ndc_y);
}

// Mouse over the 3D view (not over ImGui): left drag on cloth pulls the vertex, elsewhere (or with
// Alt) orbits; right or middle drag pans; the wheel zooms. Hovering shows the vertex under the cursor.
// A recording has nothing to pull: there a left drag always orbits.
class MouseControl {
 public:
  // `bvhs`: the displayed cloths' hierarchies, for picking.
  void update(OrbitCamera& camera, SimulationSession& session, ViewerState& state, const Viewport& viewport,
              const std::vector<Bvh>& bvhs, bool can_pull) {
    const ImGuiIO& io = ImGui::GetIO();
    World& world = session.world();
    const Ray ray = mouse_ray(camera, viewport);
    state.hover = {};
    if (drag_.active()) {
      if (!io.MouseDown[0]) {
        drag_.end(world);
      } else {
        drag_.move_to(point_on_view_plane(ray, drag_plane_point_, -camera_forward(camera)));
        state.hover = {true, drag_.cloth(), drag_.vertex()};
        return;
      }
    }
    if (io.WantCaptureMouse) {
      orbiting_ = false;
      return;
    }
    const std::optional<VertexPick> pick = pick_vertex(world.cloths(), ray, &bvhs);
    if (pick) state.hover = {true, pick->cloth, pick->vertex};
    if (ImGui::IsMouseClicked(0)) {
      orbiting_ = io.KeyAlt || !pick || !can_pull;
      if (!orbiting_) {
        drag_plane_point_ = pick->hit;
        drag_.begin(pick->cloth, pick->vertex, pick->hit);
        return;
      }
    }
    if (!io.MouseDown[0]) orbiting_ = false;
    if (orbiting_) camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
    if (io.MouseDown[1] || io.MouseDown[2]) {
      // Mouse motion comes in window units; pan works in framebuffer pixels.
      const double scale = viewport.pixel_scale();
      camera.pan(io.MouseDelta.x * scale, io.MouseDelta.y * scale, viewport.framebuffer_height);
    }
    if (io.MouseWheel != 0.0f) camera.zoom(io.MouseWheel);
  }

  void release(World& world) { drag_.end(world); }
  const VertexDrag& drag() const { return drag_; }

 private:
  static Vec3 camera_forward(const OrbitCamera& camera) { return (camera.target() - camera.eye()).normalized(); }

  VertexDrag drag_;
  Vec3 drag_plane_point_ = Vec3::Zero();
  bool orbiting_ = false;
};

bool key_pressed(int glfw_key) { return ImGui::IsKeyPressed(glfw_key, false); }
bool key_down(int glfw_key) { return ImGui::IsKeyDown(glfw_key); }

// Keyboard shortcuts (ignored while an ImGui field has focus).
void handle_keys(const SimulationSession& session, ViewerState& state, OrbitCamera& camera,
                 const Viewport& viewport) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureKeyboard) return;
  if (key_pressed(GLFW_KEY_SPACE)) state.requests.toggle_play = true;
  if (key_pressed(GLFW_KEY_N)) state.requests.step = true;
  if (key_pressed(GLFW_KEY_R)) state.requests.reset = true;
  if (key_pressed(GLFW_KEY_F)) camera.frame(world_bounds(session.world()), viewport.aspect());
  if (key_pressed(GLFW_KEY_W)) state.view.wireframe = !state.view.wireframe;
  if (key_pressed(GLFW_KEY_B)) state.view.boxes = !state.view.boxes;
  if (key_pressed(GLFW_KEY_C)) state.view.contacts = !state.view.contacts;
  if (key_pressed(GLFW_KEY_T)) state.view.strain = !state.view.strain;
  if (key_pressed(GLFW_KEY_L)) state.view.subdivision_levels = (state.view.subdivision_levels + 1) % 3;
  if (key_pressed(GLFW_KEY_P) || key_pressed(GLFW_KEY_F12)) state.save_screenshot = true;
  if (key_pressed(GLFW_KEY_F5)) state.reload_shaders = true;
  if (key_pressed(GLFW_KEY_LEFT_BRACKET)) state.view.box_depth = std::max(0, state.view.box_depth - 1);
  if (key_pressed(GLFW_KEY_RIGHT_BRACKET)) state.view.box_depth = std::min(12, state.view.box_depth + 1);
  // Arrows orbit (pan with Shift), +/- or Page Up/Down zoom; speeds per drawn frame.
  const double step = 6.0;
  const double dx = (key_down(GLFW_KEY_RIGHT) ? step : 0.0) - (key_down(GLFW_KEY_LEFT) ? step : 0.0);
  const double dy = (key_down(GLFW_KEY_DOWN) ? step : 0.0) - (key_down(GLFW_KEY_UP) ? step : 0.0);
  if (dx != 0.0 || dy != 0.0) {
    if (io.KeyShift) {
      camera.pan(dx, dy, viewport.framebuffer_height);
    } else {
      camera.orbit(dx, dy);
    }
  }
  if (key_down(GLFW_KEY_EQUAL) || key_down(GLFW_KEY_KP_ADD) || key_down(GLFW_KEY_PAGE_UP)) camera.zoom(0.1);
  if (key_down(GLFW_KEY_MINUS) || key_down(GLFW_KEY_KP_SUBTRACT) || key_down(GLFW_KEY_PAGE_DOWN)) camera.zoom(-0.1);
}

// A tooltip on the hovered vertex: index, pinned or free, position and speed.
void draw_hover_tooltip(const SimulationSession& session, const ViewerState& state, bool dragging) {
  if (!state.hover.valid || ImGui::GetIO().WantCaptureMouse) return;
  const Cloth& cloth = session.world().cloths()[static_cast<size_t>(state.hover.cloth)];
  const int v = state.hover.vertex;
  const Vec3 x = cloth.state.x.col(v);
  ImGui::BeginTooltip();
  ImGui::Text("cloth %d, vertex %d: %s%s", state.hover.cloth, v, cloth.model.inverse_mass[v] == 0.0 ? "pinned" : "free",
              dragging ? ", dragged" : "");
  ImGui::Text("x = (%.3f, %.3f, %.3f) m", x.x(), x.y(), x.z());
  ImGui::Text("|v| = %.3f m/s, mass %.3g kg", cloth.state.v.col(v).norm(), cloth.model.mass[v]);
  ImGui::EndTooltip();
}

// Synthetic contacts spread over the first cloth, all four colours with impulse arrows: they
// exercise the contact display with every colour whatever the scene touches.
std::vector<ContactRecord> synthetic_contacts(const World& world) {
  std::vector<ContactRecord> contacts;
  if (world.cloths().empty()) return contacts;
  const Cloth& cloth = world.cloths().front();
  const Positions normals = vertex_normals(cloth.state.x, cloth.model.triangles);
  for (int i = 0, k = 0; i < cloth.num_vertices(); i += 23, ++k) {
    ContactRecord contact;
    contact.kind = k % 2 == 0 ? ContactKind::vertex_face : ContactKind::edge_edge;
    contact.partners = (k / 2) % 2 == 0 ? ContactPartners::cloth_solid : ContactPartners::cloth_cloth;
    contact.position = cloth.state.x.col(i);
    contact.normal = normals.col(i).normalized();
    contact.impulse = 1e-3;
    contacts.push_back(contact);
  }
  return contacts;
}

// The first PREFIX_NNNN.png that does not exist yet.
std::string next_free_png(const std::string& prefix) {
  for (int n = 0;; ++n) {
    char name[32];
    std::snprintf(name, sizeof(name), "_%04d.png", n);
    if (!std::filesystem::exists(prefix + name)) return prefix + name;
  }
}

// Every OpenGL error raised since the last call, as one message (empty if none).
std::string take_gl_errors() {
  std::string message;
  for (GLenum error = glGetError(); error != GL_NO_ERROR; error = glGetError()) {
    char code[32];
    std::snprintf(code, sizeof(code), "%s0x%04x", message.empty() ? "" : ", ", error);
    message += code;
  }
  return message;
}

// The display switches of the scene's "view", then the command line's --show, which win.
std::vector<std::string> display_switches(const ViewerOptions& options, const SceneView& scene_view) {
  std::vector<std::string> switches = scene_view.show;
  switches.insert(switches.end(), options.show.begin(), options.show.end());
  return switches;
}

// What the view shows at start: the scene's "view" (docs/scenes.md) with the command line over it.
ViewOptions view_options_from(const ViewerOptions& options, const SceneView& scene_view) {
  ViewOptions view;
  view.subdivision_levels = std::clamp(options.subdivision, 0, 2);
  view.box_depth = std::max(options.box_depth, 0);
  view.impulse_scale = scene_view.impulse_scale;
  view.max_arrow_length = scene_view.max_arrow_length;
  // Names as in display_switch_names (io/scene_file.hpp); "no-" turns the switch off.
  for (const std::string& item : display_switches(options, scene_view)) {
    const bool on = item.rfind("no-", 0) != 0;
    const std::string name = on ? item : item.substr(3);
    if (name == "boxes") view.boxes = on;
    if (name == "contacts") view.contacts = on;
    if (name == "wireframe") view.wireframe = on;
    if (name == "strain") view.strain = on;
    if (name == "pins") view.pins = on;
    if (name == "grid") view.ground_grid = on;
    if (name == "colliders") view.colliders = on;
    if (name == "cutaway") view.cutaway = on;
    if (name == "tangles") view.tangles = on;
  }
  return view;
}

// Whether the display switches turn the tangle marks off ("no-tangles" after any "tangles"),
// which a scene that starts tangled otherwise turns on.
bool tangles_switched_off(const ViewerOptions& options, const SceneView& scene_view) {
  bool off = false;
  for (const std::string& item : display_switches(options, scene_view)) {
    if (item == "tangles" || item == "no-tangles") off = item == "no-tangles";
  }
  return off;
}

// Whether saved pictures include the panels: "panels" asked for, or a panel to open (asking for a
// panel means wanting to see it), unless "no-panels" comes last.
bool panels_in_pictures(const ViewerOptions& options, const SceneView& scene_view) {
  bool panels = !options.open_panels.empty();
  for (const std::string& item : display_switches(options, scene_view)) {
    if (item == "panels") panels = true;
    if (item == "no-panels") panels = false;
  }
  return panels;
}

// The camera where the scene's "view" puts it: its angles, the whole scene framed, then its target
// and distance where it gives them.
void place_camera(OrbitCamera& camera, const SceneView& scene_view, const World& world, double aspect) {
  camera.set_angles(scene_view.yaw_degrees * pi / 180.0, scene_view.pitch_degrees * pi / 180.0);
  camera.frame(world_bounds(world), aspect);
  if (scene_view.has_target) camera.set_target(scene_view.target);
  if (scene_view.distance > 0.0) camera.set_distance(scene_view.distance);
  // A view chosen for a later frame still shows all of every cloth at the first.
  Eigen::AlignedBox3d cloths;
  for (const Cloth& cloth : world.cloths()) {
    for (int i = 0; i < cloth.num_vertices(); ++i) cloths.extend(Vec3(cloth.state.x.col(i)));
  }
  camera.keep_in_view(cloths, aspect);
}

// A loaded or reset scene's first frame, checked; a tangled start is said on stderr. Returns
// whether it is tangled.
bool say_start_tangles(const SimulationSession& session) {
  WorldTangles tangles;
  const TangleReport report = tangles.check(session.world());
  say_if_tangled_at_start(session.scene_path(), report, tangles.input());
  return !report.clean();
}

// The shown frame's intersecting triangle pairs, checked again only when the world has moved on
// (or a vertex is being dragged), since the exact check costs about a millisecond per thousand
// triangles.
class TangleMarks {
 public:
  // `pairs`: set to one line per intersecting pair.
  void add_to(DebugOverlay& overlay, const World& world, int generation, bool dragging,
              std::vector<std::string>& pairs) {
    if (generation != checked_generation_ || world.time() != checked_time_ || dragging) {
      if (generation != checked_generation_)
        tangles_ = WorldTangles();  // a new start decides what holds what
      report_ = tangles_.check(world);
      checked_generation_ = generation;
      checked_time_ = world.time();
    }
    const TangleInput& input = tangles_.input();
    const int num_cloths = static_cast<int>(input.cloths.size());
    const auto surface = [&](int index) -> const NamedSurface& {
      return index < num_cloths ? input.cloths[index] : input.colliders[index - num_cloths];
    };
    const Color magenta(1.0f, 0.1f, 0.9f);
    pairs.clear();
    for (const TriangleIntersection& pair : report_.pairs) {
      pairs.push_back(surface(pair.mesh_a).name + " triangle " + std::to_string(pair.triangle_a) + " x " +
                      surface(pair.mesh_b).name + " triangle " + std::to_string(pair.triangle_b));
      for (const auto& [mesh, triangle] :
           {std::pair(pair.mesh_a, pair.triangle_a), std::pair(pair.mesh_b, pair.triangle_b)}) {
        const NamedSurface& s = surface(mesh);
        for (int k = 0; k < 3; ++k) {
          overlay.add_line(s.positions->col((*s.triangles)(k, triangle)),
                           s.positions->col((*s.triangles)((k + 1) % 3, triangle)), magenta);
        }
      }
    }
  }

 private:
  WorldTangles tangles_;
  TangleReport report_;
  int checked_generation_ = -1;
  double checked_time_ = 0.0;
};

// Runs the window until it is closed, or draws one screenshot. Returns the exit code.
// The viewer's window loop: each drawn frame polls input, draws the panels, sends their requests
// and settings to the simulation worker and takes in its last finished step, follows the shown
// world into the renderer, draws, and saves the pictures asked for. One phase per member
// function; the locals of a frame live here.
class ViewerLoop {
 public:
  // `player`: a recording to show instead of the worker's steps (`weft view`), else null.
  ViewerLoop(GLFWwindow* window, SimulationWorker& worker, RecordingPlayer* player,
             const ViewerOptions& options, const std::string& shader_dir, bool starts_tangled)
      : window_(window),
        worker_(worker),
        player_(player),
        options_(options),
        imgui_(window),
        renderer_(shader_dir),
        screenshot_(!options.screenshot_path.empty()),
        record_dir_(options.record_dir.empty() ? "weft_record" : options.record_dir),
        record_progress_(0, true, {"recording into " + record_dir_ + " (pictures)", 2.0, 5.0}) {
    const SimulationSession& session = worker.shown();
    state_.view = view_options_from(options, session.scene().view);
    if (starts_tangled && !tangles_switched_off(options, session.scene().view)) state_.view.tangles = true;
    state_.panels_in_pictures = panels_in_pictures(options, session.scene().view);
    state_.scene_files = list_scene_files(std::filesystem::path(session.scene_path()).parent_path().string());
    if (state_.scene_files.empty()) state_.scene_files.push_back(session.scene_path());
    meshes_ = show_world(renderer_, session.world(), state_.view);
    shown_generation_ = session.generation();
    read_viewport();
    place_camera(camera_, session.scene().view, session.world(), viewport_.aspect());
    shown_scene_ = session.scene_path();
    // ImGui lays its windows out over a few frames: a picture with panels is taken on the third.
    screenshot_frames_left_ = state_.panels_in_pictures ? 3 : 1;
    state_.record_frames = !options.record_dir.empty();
    if (options.play && !screenshot_) state_.requests.toggle_play = true;
    if (player_ != nullptr) state_.requests.show_frame = options.recording_frame;
  }
  ViewerLoop(const ViewerLoop&) = delete;
  ViewerLoop& operator=(const ViewerLoop&) = delete;

  // Returns the program's exit code: 0, 4 (a picture could not be saved) or 5 (an OpenGL error
  // in a screenshot run).
  int run() {
    if (player_ != nullptr) {
      // The frame asked for, before the first picture (the camera was placed at frame 0).
      if (!show_recorded(options_.recording_frame) && screenshot_) return 2;
      state_.requests.show_frame = -1;
    } else if (screenshot_) {
      simulate_screenshot_frames();
    }
    using Clock = std::chrono::steady_clock;
    const Clock::time_point opened = Clock::now();
    Clock::time_point last_time = opened;
    while (screenshot_ || !glfwWindowShouldClose(window_)) {
      const Clock::time_point now = Clock::now();
      const double interval = std::chrono::duration<double>(now - last_time).count();
      const double wall_seconds = std::min(interval, 0.25);
      last_time = now;
      const double open_seconds = std::chrono::duration<double>(now - opened).count();
      if (options_.quit_after_seconds > 0.0 && open_seconds >= options_.quit_after_seconds) break;
      glfwPollEvents();
      read_viewport();

      imgui_.begin_frame();
      if (!screenshot_) {
        mouse_.update(camera_, shown(), state_, viewport_, meshes_.cloth_bvhs, player_ == nullptr);
        handle_keys(shown(), state_, camera_, viewport_);
      }
      draw_panels();
      send_requests();
      take_in_simulation(wall_seconds);
      follow_world();
      build_frame_overlay();
      renderer_.draw(camera_, viewport_.framebuffer_width, viewport_.framebuffer_height, overlay_,
                     viewport_.pixel_scale());
      const std::string gl_errors = take_gl_errors();
      if (!gl_errors.empty()) {
        std::fprintf(stderr, "weft: OpenGL error after drawing: %s\n", gl_errors.c_str());
        if (screenshot_) return 5;
      }
      // Pictures show the 3D view only unless asked: the panels are drawn after they are read.
      if (state_.panels_in_pictures) imgui_.end_frame();
      const bool take_screenshot = screenshot_ && --screenshot_frames_left_ == 0;
      if (!save_pictures(take_screenshot)) return 4;
      if (!state_.panels_in_pictures) imgui_.end_frame();
      if (!options_.frame_times_path.empty()) log_frame_time(open_seconds, now, interval);
      glfwSwapBuffers(window_);
      if (take_screenshot) break;
    }
    if (recorded_ > 0) record_progress_.finish(recorded_);
    if (!options_.frame_times_path.empty()) {
      try {
        frame_times_.write(options_.frame_times_path);
      } catch (const IoError& error) {
        std::fprintf(stderr, "weft: %s\n", error.what());
        return 4;
      }
    }
    return 0;
  }

 private:
  void read_viewport() {
    glfwGetFramebufferSize(window_, &viewport_.framebuffer_width, &viewport_.framebuffer_height);
    glfwGetWindowSize(window_, &viewport_.window_width, &viewport_.window_height);
  }

  SimulationSession& shown() { return worker_.shown(); }

  void log_frame_time(double open_seconds, std::chrono::steady_clock::time_point frame_start,
                      double interval) {
    FrameTime frame;
    frame.start_s = open_seconds;
    frame.work_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start).count();
    frame.interval_ms = 1e3 * interval;
    frame.shown_step = shown().frame() * shown().schedule().steps_per_frame + shown().step_in_frame();
    frame.step_ms = shown().world().last_step_stats().total_ms;
    frame.simulated_s = shown().world().time();
    frame_times_.add(frame);
  }

  // Screenshot: a fixed number of frames, independent of wall time, before the one picture;
  // progress lines once it takes longer than a moment.
  void simulate_screenshot_frames() {
    ProgressReporter progress(options_.frames, true, {"screenshot " + options_.screenshot_path, 2.0, 1.0});
    for (int frame = 0; frame < options_.frames; ++frame) {
      worker_.submit([](SimulationSession& session) { session.advance_frame(); });
      worker_.wait_for_commands();
      worker_.exchange(mouse_.drag(), state_.speed);
      state_.history.record(shown().world());
      progress.update(shown().frame());
    }
    progress.finish(shown().frame());
  }

  void draw_panels() {
    if (player_ != nullptr) {
      // A recording: its timeline and plots; no solver, material or live plots to edit.
      draw_recording_panel(*player_, state_);
      draw_debug_panel(shown(), state_);
    } else {
      draw_simulation_panel(shown(), state_);
      draw_solver_panel(shown());
      draw_material_panel(shown());
      draw_debug_panel(shown(), state_);
      draw_plots_panel(state_);
      draw_status_line(shown(), state_);
    }
    draw_hover_tooltip(shown(), state_, mouse_.drag().active());
    if (first_frame_) {
      // Panels asked for on the command line: expanded and in front from the next frame on.
      for (const std::string& name : options_.open_panels) {
        ImGui::SetWindowCollapsed(name.c_str(), false);
        ImGui::SetWindowFocus(name.c_str());
      }
      first_frame_ = false;
    }
  }

  // The panels' and keys' requests, sent to the worker as commands. Play and pause show at once.
  // A recorded frame into the shown world; an unreadable frame file is said and playback stops.
  bool show_recorded(int frame) {
    try {
      player_->show(shown(), frame);
      return true;
    } catch (const IoError& error) {
      std::fprintf(stderr, "weft view: %s\n", error.what());
      player_->playing = false;
      return false;
    }
  }

  // In a recording the requests move through its frames: play, one frame on, back to frame 0.
  void send_recording_requests() {
    SessionRequests& requests = state_.requests;
    const int last = player_->frames() - 1;
    if (requests.toggle_play) {
      if (!player_->playing && player_->frame() == last) show_recorded(0);
      player_->playing = !player_->playing;
    }
    if (requests.step || requests.frame) requests.show_frame = std::min(player_->frame() + 1, last);
    if (requests.reset) requests.show_frame = 0;
    if (requests.show_frame >= 0) show_recorded(requests.show_frame);
    requests = {};
  }

  void set_playing(bool playing) {
    shown().playing = playing;
    worker_.submit([playing](SimulationSession& session) { session.playing = playing; });
  }

  // Looking back through the worker's history: a kept frame shown (paused), then back to the
  // latest, or on from the frame shown. Play while looking back plays from the latest.
  void send_history_requests() {
    SessionRequests& requests = state_.requests;
    if (requests.history_frame >= 0) {
      if (shown().playing) set_playing(false);
      if (std::shared_ptr<const Checkpoint> checkpoint = worker_.history_frame(requests.history_frame)) {
        scrubbed_ = std::move(checkpoint);
        shown().show_checkpoint(*scrubbed_);
        state_.scrubbed_frame = scrubbed_->frame;
      }
    }
    if (scrubbed_ == nullptr) return;
    if (requests.resume_shown) {
      worker_.resume_from(scrubbed_->frame);
    } else if (requests.resume_latest || requests.toggle_play) {
      worker_.submit([](SimulationSession&) {});  // publishes the latest again
    } else {
      return;
    }
    requests.toggle_play = false;
    set_playing(true);
    scrubbed_ = nullptr;
    state_.scrubbed_frame = -1;
  }

  void send_requests() {
    if (player_ != nullptr) return send_recording_requests();
    send_history_requests();
    SessionRequests& requests = state_.requests;
    if (requests.toggle_play) {
      shown().playing = !shown().playing;
      worker_.submit([playing = shown().playing](SimulationSession& session) { session.playing = playing; });
    }
    if (requests.step) worker_.submit([](SimulationSession& session) { session.advance_step(); });
    if (requests.frame) worker_.submit([](SimulationSession& session) { session.advance_frame(); });
    if (requests.reset) worker_.submit([](SimulationSession& session) { session.reset(); });
    if (!requests.load.empty())
      worker_.submit([file = requests.load](SimulationSession& session) { session.load(file); });
    if (requests.clear_error) {
      shown().clear_error();
      worker_.submit([](SimulationSession& session) { session.clear_error(); });
    }
    requests = {};
  }

  // The panels' settings and the drag go to the worker; the last finished step comes back.
  void take_in_simulation(double wall_seconds) {
    count_frame(wall_seconds);
    if (player_ != nullptr) {
      if (!screenshot_ && player_->advance(wall_seconds, state_.speed)) show_recorded(player_->frame());
      return;
    }
    const int generation = shown().generation();
    const double time_before = shown().world().time();
    const bool changed = !screenshot_ && worker_.exchange(mouse_.drag(), state_.speed);
    if (changed && scrubbed_ != nullptr) {
      if (shown().generation() == generation) {
        shown().show_checkpoint(*scrubbed_);  // still looking back
      } else {
        scrubbed_ = nullptr;  // another world: its history is gone
        state_.scrubbed_frame = -1;
      }
    } else if (changed && shown().generation() == generation && shown().world().time() != time_before) {
      state_.history.record(shown().world());
    }
    state_.kept_frames = worker_.history();
    state_.real_time_factor = worker_.rates().real_time_factor;
    state_.steps_per_second = worker_.rates().steps_per_second;
  }

  // The window's frames per second, counted over half a second.
  void count_frame(double wall_seconds) {
    ++fps_frames_;
    fps_seconds_ += wall_seconds;
    if (fps_seconds_ >= 0.5) {
      state_.frames_per_second = fps_frames_ / fps_seconds_;
      fps_frames_ = 0;
      fps_seconds_ = 0.0;
    }
  }

  // The renderer follows the world: shaders reloaded when asked, the meshes registered again after
  // a reload, a reset or a new subdivision level, else new positions pushed.
  void follow_world() {
    if (state_.reload_shaders) {
      state_.reload_shaders = false;
      state_.shader_message = renderer_.reload_shaders();
    }
    // Views follow the world: re-register after a reload or a new subdivision level, else push positions.
    if (shown().generation() != shown_generation_ ||
        state_.view.subdivision_levels != meshes_.subdivision_levels) {
      if (shown().generation() != shown_generation_) {
        mouse_.release(shown().world());
        state_.history.clear();
      }
      if (shown().scene_path() != shown_scene_) {
        // Another scene opens as its file says; a reset of the same one keeps the camera and switches.
        shown_scene_ = shown().scene_path();
        state_.view = view_options_from(options_, shown().scene().view);
        place_camera(camera_, shown().scene().view, shown().world(), viewport_.aspect());
      }
      if (shown().generation() != shown_generation_ && say_start_tangles(shown()) &&
          !tangles_switched_off(options_, shown().scene().view)) {
        state_.view.tangles = true;
      }
      meshes_ = show_world(renderer_, shown().world(), state_.view);
      shown_generation_ = shown().generation();
    } else {
      update_world(renderer_, meshes_, shown().world(), state_.view);
    }
  }

  // What the 3D view draws over the cloth: boxes, contacts, tangles, the dragged vertex.
  void build_frame_overlay() {
    update_bvhs(meshes_, shown().world());  // drawn with --show boxes, and used for picking
    if (options_.test_contacts) {
      build_overlay(overlay_, shown().world(), meshes_, state_.view, synthetic_contacts(shown().world()));
    } else {
      build_overlay(overlay_, shown().world(), meshes_, state_.view, shown().world().contacts());
    }
    if (state_.view.tangles)
      tangle_marks_.add_to(overlay_, shown().world(), shown().generation(), mouse_.drag().active(),
                           state_.tangle_pairs);
    if (mouse_.drag().active()) {
      const Cloth& cloth = shown().world().cloths()[static_cast<size_t>(mouse_.drag().cloth())];
      overlay_.add_line(cloth.state.x.col(mouse_.drag().vertex()), mouse_.drag().target(),
                        Color(1.0f, 1.0f, 1.0f));
      overlay_.points.push_back({mouse_.drag().target(), Color(1.0f, 1.0f, 1.0f), 6.0f});
    }
  }

  // The screenshot_ of a screenshot_ run, a picture asked for in the panel, a recorded frame.
  // Returns false when a screenshot_ run could not save its picture.
  bool save_pictures(bool take_screenshot) {
    try {
      if (take_screenshot)
        save_back_buffer_png(options_.screenshot_path, viewport_.framebuffer_width,
                             viewport_.framebuffer_height);
      if (state_.save_screenshot) {
        state_.save_screenshot = false;
        state_.last_saved = next_free_png("weft_screenshot");
        save_back_buffer_png(state_.last_saved, viewport_.framebuffer_width, viewport_.framebuffer_height);
      }
      if (state_.record_frames && !screenshot_) {
        std::filesystem::create_directories(record_dir_);
        char name[32];
        std::snprintf(name, sizeof(name), "/frame_%05d.png", recorded_++);
        save_back_buffer_png(record_dir_ + name, viewport_.framebuffer_width, viewport_.framebuffer_height);
        record_progress_.update(recorded_);
      }
    } catch (const IoError& error) {
      std::fprintf(stderr, "weft: %s\n", error.what());
      if (screenshot_) return false;
      state_.last_saved = error.what();
      state_.record_frames = false;
    } catch (const std::filesystem::filesystem_error& error) {
      state_.last_saved = error.what();
      state_.record_frames = false;
    }
    return true;
  }

  GLFWwindow* window_;
  SimulationWorker& worker_;
  RecordingPlayer* player_;
  std::shared_ptr<const Checkpoint> scrubbed_;  // the history frame shown, null when the latest
  const ViewerOptions& options_;
  ImGuiLayer imgui_;
  Renderer renderer_;
  ViewerState state_;
  TangleMarks tangle_marks_;
  WorldMeshes meshes_;
  int shown_generation_ = 0;
  std::string shown_scene_;
  DebugOverlay overlay_;
  MouseControl mouse_;
  Viewport viewport_;
  OrbitCamera camera_;
  const bool screenshot_;
  int screenshot_frames_left_ = 1;
  bool first_frame_ = true;
  const std::string record_dir_;
  int recorded_ = 0;
  ProgressReporter record_progress_;  // pictures saved so far, every few seconds while recording
  FrameTimeLog frame_times_;          // --frame-times
  int fps_frames_ = 0;                // count_frame's window
  double fps_seconds_ = 0.0;
};

// `weft view DIR`: the recording, a session built from its run.json's scene, checked to match.
void open_recording(const ViewerOptions& options, std::optional<SimulationSession>& session,
                    std::optional<RecordingPlayer>& player) {
  const std::filesystem::path dir = options.recording_dir;
  Recording recording = read_recording(dir);
  StatsTable stats;
  if (std::filesystem::exists(dir / "stats.csv")) stats = read_stats_table(dir / "stats.csv");
  SceneDesc scene = recording.scene;
  session.emplace(SimulationSession::from_scene((dir / "run.json").string(), std::move(scene)));
  player.emplace(std::move(recording), std::move(stats));
  player->check_matches(*session);
  if (options.recording_frame >= player->frames()) {
    throw IoError(options.recording_dir + ": --frame " + std::to_string(options.recording_frame) +
                  ": the recording has frames 0 to " + std::to_string(player->frames() - 1));
  }
}

int run_window(GLFWwindow* window, SimulationSession session, RecordingPlayer* player,
               const ViewerOptions& options, const std::string& shader_dir, bool starts_tangled) {
  SimulationWorker worker(std::move(session), static_cast<size_t>(options.history_mb) << 20);
  ViewerLoop loop(window, worker, player, options, shader_dir, starts_tangled);
  return loop.run();
}

}  // namespace

int run_viewer(const ViewerOptions& options) {
  // The scene (or recording) is checked before any window opens, so a bad file fails the same way
  // everywhere.
  std::optional<SimulationSession> session;
  std::optional<RecordingPlayer> player;
  const bool recording = !options.recording_dir.empty();
  const char* prefix = recording ? "weft view" : "weft";
  try {
    if (recording) {
      open_recording(options, session, player);
    } else {
      session.emplace(options.scene_path, options.overrides);
    }
  } catch (const SceneError& error) {
    std::fprintf(stderr, "%s: %s\n", prefix, error.what());
    return 2;
  } catch (const IoError& error) {
    std::fprintf(stderr, "%s: %s\n", prefix, error.what());
    return 2;
  }
  session->set_threads(options.threads);
  const bool starts_tangled = say_start_tangles(*session);

  // Installed (PREFIX/bin/weft beside PREFIX/share/weft/shaders), else the source tree built from.
  std::string shader_dir;
  try {
    shader_dir = find_data_dir(
        {executable_dir().empty() ? "" : executable_dir() + "/../share/weft/shaders", WEFT_SHADER_DIR},
        "mesh.vert", "the viewer's shaders");
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 1;
  }

  glfwSetErrorCallback(report_glfw_error);
  GlfwLibrary glfw;
  const char* no_window_message =
      "weft: cannot open a window (no display?); run headless instead: weft --headless SCENE --out DIR\n";
  if (!glfw.ok()) {
    std::fputs(no_window_message, stderr);
    return 1;
  }
  Window window(options, "Weft - " + (recording ? options.recording_dir : options.scene_path));
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
    return run_window(window.get(), std::move(*session), player ? &*player : nullptr, options, shader_dir,
                      starts_tangled);
  } catch (const RenderError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 1;
  }
}

}  // namespace weft
