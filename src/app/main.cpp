// weft: the viewer by default, or a headless recording with --headless.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/headless_runner.hpp"
#include "weft/version.hpp"
#ifdef WEFT_HAS_VIEWER
#include "app/viewer.hpp"
#endif

int main(int argc, char** argv) {
  CLI::App app{"Weft: cloth and soft-body simulation"};
  std::string scene_path = "scenes/default.json";
  bool headless = false;
  std::string out_dir;
  int frames = -1;
  std::vector<std::string> overrides;
  std::string screenshot;
  bool quiet = false;
  int threads = 1;
  bool version = false;
  std::string record_dir;
  std::vector<std::string> open_panels;
  std::vector<std::string> show;
  int box_depth = 0;
  int subdivision = 0;
  bool test_contacts = false;

  app.add_option("scene", scene_path, "Scene file (JSON)")->capture_default_str();
  app.add_flag("--headless", headless, "Run without a window and record to --out");
  app.add_option("--out", out_dir, "Output folder of a headless run");
  app.add_option("--frames", frames, "Frames to simulate (overrides the scene's \"frames\")")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--set", overrides, "Override a scene field: path=value (e.g. solver.time_step=0.001)")
      ->take_all();
  app.add_option("--screenshot", screenshot, "Viewer: simulate --frames frames, save a PNG and exit");
  app.add_option("--record", record_dir, "Viewer: save every drawn frame as DIR/frame_NNNNN.png");
  app.add_option("--show", show,
                 "Viewer display switches: boxes, contacts, no-contacts, wireframe, strain, no-pins, no-grid, no-colliders, "
                 "panels (the ImGui panels in saved pictures too)")
      ->delimiter(',')
      ->check(CLI::IsMember({"boxes", "contacts", "no-contacts", "wireframe", "strain", "no-pins", "no-grid",
                             "no-colliders", "panels"}));
  app.add_option("--open-panel", open_panels, "Viewer: start with this panel expanded and in front")
      ->check(CLI::IsMember({"Simulation", "Solver", "Material", "Display and collisions", "Plots"}));
  app.add_option("--box-depth", box_depth, "Viewer: bounding-box hierarchy depth shown with --show boxes")
      ->check(CLI::Range(0, 16));
  app.add_option("--subdivide", subdivision, "Viewer: Loop subdivision levels of the displayed cloth")
      ->check(CLI::Range(0, 2));
  app.add_flag("--test-contacts", test_contacts, "Viewer: draw synthetic contacts (tests the contact display)");
  app.add_flag("--quiet", quiet, "Headless: no progress output");
  app.add_option("--threads", threads, "Solver threads (0: all cores)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--version", version, "Print the version and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    app.exit(error);
    return 2;
  }

  if (version) {
    std::printf("weft %s (%s)\n", weft::version_string, weft::git_commit);
    return 0;
  }
  if (headless) {
    if (out_dir.empty()) {
      std::fprintf(stderr, "weft: --headless needs --out DIR, the folder to record into\n");
      return 2;
    }
    if (!screenshot.empty()) {
      std::fprintf(stderr, "weft: --screenshot needs the viewer; it cannot be combined with --headless\n");
      return 2;
    }
    return weft::run_headless({scene_path, overrides, out_dir, frames, quiet, threads});
  }
#ifdef WEFT_HAS_VIEWER
  weft::ViewerOptions options;
  options.scene_path = scene_path;
  options.overrides = overrides;
  options.screenshot_path = screenshot;
  options.frames = frames < 0 ? 0 : frames;
  options.record_dir = record_dir;
  options.show = show;
  options.open_panels = open_panels;
  options.box_depth = box_depth;
  options.subdivision = subdivision;
  options.test_contacts = test_contacts;
  return weft::run_viewer(options);
#else
  std::fprintf(stderr,
               "weft: this build has no viewer (built with WEFT_VIEWER=OFF); run headless instead:\n"
               "  weft --headless %s --out DIR\n",
               scene_path.c_str());
  return 1;
#endif
}
