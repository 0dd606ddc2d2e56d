// weft: the viewer by default, a headless recording with --headless, and the `sweep`, `plot`
// and `check` commands. This file only reads the command line and dispatches.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/check_recording.hpp"
#include "app/headless_runner.hpp"
#include "app/openmp_wait_policy.hpp"
#include "app/plot.hpp"
#include "app/sweep.hpp"
#include "core/error.hpp"
#include "io/scene_file.hpp"
#include "io/sweep_file.hpp"
#include "sim/scene_desc.hpp"
#include "sim/world.hpp"
#include "weft/version.hpp"
#ifdef WEFT_HAS_VIEWER
#include "app/viewer.hpp"
#endif

namespace {

// An integer option in [min, max]; `what` says what it counts, for the message CLI11 prefixes
// with the option's name ("--frames: expected a whole number of frames >= 0, got 'abc'").
CLI::Validator whole_number(const std::string& what, long long min, long long max, const std::string& range) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const long long value = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || errno == ERANGE || value < min || value > max) {
          return "expected a whole number of " + what + " " + range + ", got '" + text + "'";
        }
        return {};
      },
      "INT");
}

// A number >= 0 (a bound; 0 turns it off).
CLI::Validator non_negative_number(const std::string& what) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(value) || value < 0.0) {
          return "expected " + what + " >= 0 (0: no bound), got '" + text + "'";
        }
        return {};
      },
      "NUMBER");
}

// A window size "WIDTHxHEIGHT" in pixels, each in [64, 8192]; parsed into `width` and `height`.
bool parse_window_size(const std::string& text, int& width, int& height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x') return false;
  if (w < 64 || w > 8192 || h < 64 || h > 8192) return false;
  width = w;
  height = h;
  return true;
}

CLI::Validator window_size() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        int width = 0, height = 0;
        if (!parse_window_size(text, width, height)) {
          return "expected WIDTHxHEIGHT in pixels, each from 64 to 8192 (e.g. 960x540), got '" + text + "'";
        }
        return {};
      },
      "WxH");
}

// Everything the command line sets: the program's options and the subcommands'.
struct CommandLine {
  weft::HeadlessOptions headless_options;
  bool headless = false;
  std::string screenshot;
  std::string format = "pc2";
  bool version = false;
  std::string record_dir;
  std::vector<std::string> open_panels;
  std::vector<std::string> show;
  int box_depth = 0;
  int subdivision = 0;
  bool test_contacts = false;
  bool play = false;
  int history_mb = 256;
  double quit_after = 0.0;
  std::string frame_times;
  std::string window_size_text = "1280x720";
  weft::SweepOptions sweep_options;
  weft::PlotOptions plot_options;
  weft::CheckOptions check_options;
  CLI::App* sweep = nullptr;
  CLI::App* plot = nullptr;
  CLI::App* check = nullptr;
  CLI::App* view = nullptr;
  std::string view_dir;
  int view_frame = 0;
};

// The options of the program itself (the viewer and --headless).
void add_run_options(CLI::App& app, CommandLine& line) {
  app.add_option("scene", line.headless_options.scene_path, "Scene file (JSON)")->capture_default_str();
  app.add_flag("--headless", line.headless, "Run without a window and record to --out");
  app.add_option("--out", line.headless_options.out_dir, "Output folder of a headless run");
  app.add_option("--frames", line.headless_options.frames,
                 "Frames to simulate (overrides the scene's \"frames\")")
      ->check(whole_number("frames", 0, weft::max_frames, ">= 0 and <= " + std::to_string(weft::max_frames)));
  // One value per --set, so `--set fps=30 scene.json` leaves the scene to the positional argument.
  app.add_option("--set", line.headless_options.overrides,
                 "Override a scene field: path=value (e.g. solver.time_step=0.001); repeat for more")
      ->allow_extra_args(false);
  app.add_option("--screenshot", line.screenshot, "Viewer: simulate --frames frames, save a PNG and exit");
  app.add_option("--record", line.record_dir, "Viewer: save every drawn frame as DIR/frame_NNNNN.png");
  app.add_option("--show", line.show,
                 "Viewer display switches, over the scene's \"view\": boxes, contacts, wireframe, strain, "
                 "pins, grid, "
                 "colliders, cutaway, panels (the ImGui panels in saved pictures too), tangles (intersecting "
                 "triangle pairs), each with a no- form "
                 "(no-contacts) that turns it off")
      ->delimiter(',')
      ->check(CLI::IsMember(weft::display_switch_names));
  app.add_option("--open-panel", line.open_panels, "Viewer: start with this panel expanded and in front")
      ->check(CLI::IsMember({"Simulation", "Solver", "Material", "Display and collisions", "Plots"}));
  app.add_option("--box-depth", line.box_depth,
                 "Viewer: bounding-box hierarchy depth shown with --show boxes")
      ->check(whole_number("levels", 0, 16, "from 0 to 16"));
  app.add_option("--subdivide", line.subdivision, "Viewer: Loop subdivision levels of the displayed cloth")
      ->check(whole_number("levels", 0, 2, "from 0 to 2"));
  app.add_option("--size", line.window_size_text,
                 "Viewer: window (and saved picture) size in pixels, WIDTHxHEIGHT")
      ->check(window_size())
      ->capture_default_str();
  app.add_flag("--test-contacts", line.test_contacts,
               "Viewer: draw synthetic contacts (tests the contact display)");
  app.add_flag("--play", line.play, "Viewer: start playing (else it opens paused; Space plays)");
  app.add_option("--history-mb", line.history_mb,
                 "Viewer: memory for the latest frames kept to scrub back through and resume from (0: none)")
      ->check(whole_number("megabytes", 0, 1 << 20, "from 0 to 1048576"))
      ->capture_default_str();
  app.add_option("--quit-after", line.quit_after, "Viewer: close the window after SECONDS of wall time")
      ->check(CLI::PositiveNumber);
  app.add_option("--frame-times", line.frame_times,
                 "Viewer: on closing, write FILE.csv with each drawn frame's time and the step it showed");
  app.add_flag("--quiet", line.headless_options.quiet, "Headless: no progress output");
  app.add_flag("--newton-log", line.headless_options.newton_log,
               "Headless: write DIR/newton.csv, one row per Newton iteration of every implicit Euler step");
  app.add_option("--threads", line.headless_options.threads,
                 "Solver threads (0: all cores; at most " + std::to_string(weft::max_threads) + ")")
      ->check(whole_number("threads", 0, weft::max_threads,
                           "from 0 (all cores) to " + std::to_string(weft::max_threads)))
      ->capture_default_str();
  app.add_flag("--fixed-threads", line.headless_options.fixed_threads,
               "Headless: always run on --threads threads (by default a step runs on one thread while that "
               "measures faster, e.g. when another process holds a core; results are the same either way)");
  app.add_option("--format", line.format,
                 "Headless recording: pc2 (rest OBJ + point cache per cloth), obj (a file "
                 "per frame) or both")
      ->check(CLI::IsMember({"pc2", "obj", "both"}))
      ->capture_default_str();
  app.add_option("--checkpoint-every", line.headless_options.checkpoint_every,
                 "Headless: write DIR/checkpoint.bin every N frames (0: never)")
      ->check(whole_number("frames", 0, weft::max_frames,
                           "from 0 (never) to " + std::to_string(weft::max_frames)));
  app.add_option("--resume", line.headless_options.resume_dir,
                 "Headless: continue the run recorded in DIR from its checkpoint");
  app.add_option("--max-speed", line.headless_options.limits.max_speed,
                 "Headless: stop (exit 3) when a vertex moves faster, m/s (0: no bound)")
      ->check(non_negative_number("a speed in m/s"))
      ->capture_default_str();
  app.add_option("--max-strain", line.headless_options.limits.max_strain,
                 "Headless: stop (exit 3) when a spring or membrane triangle stretches more, as "
                 "stretch - 1 (0: no bound)")
      ->check(non_negative_number("a strain"))
      ->capture_default_str();
  app.add_flag("--version", line.version, "Print the version and exit");
}

// The subcommands: sweep, plot, check and view.
void add_subcommands(CLI::App& app, CommandLine& line) {
  line.sweep =
      app.add_subcommand("sweep", "Run a grid of scene overrides locally, or write a SLURM array job");
  line.sweep->add_option("sweep_file", line.sweep_options.sweep_file, "Sweep file (JSON, docs/sweeps.md)")
      ->required();
  line.sweep->add_flag("--slurm", line.sweep_options.slurm,
                       "Write an sbatch array script instead of running");
  line.sweep->add_option("--out", line.sweep_options.out_dir,
                         "Sweep folder (default: the sweep file's \"out\")");
  line.sweep
      ->add_option("--jobs,-j", line.sweep_options.jobs, "Local runs at once (default: cores / threads)")
      ->check(whole_number("runs at once", 1, weft::max_sweep_jobs,
                           "from 1 to " + std::to_string(weft::max_sweep_jobs)));
  CLI::Option* dry_run =
      line.sweep->add_flag("--dry-run", line.sweep_options.dry_run, "List the case names and exit");
  line.sweep
      ->add_flag("--status", line.sweep_options.status,
                 "Say per case: complete, running, interrupted, failed, changed or not started; exit 0 "
                 "when all are complete, 1 when some are not yet, 5 when some failed")
      ->excludes(dry_run)
      ->excludes("--slurm");

  line.plot = app.add_subcommand("plot", "Plot a run's (or a sweep's) stats.csv to PNG with gnuplot");
  line.plot->add_option("dir", line.plot_options.dir, "Run or sweep folder")->required();

  line.check = app.add_subcommand(
      "check",
      "Check every frame of a headless recording for intersecting triangles and vertices inside "
      "colliders; exit 0 all clean, 1 some frame tangled, 2 bad input");
  line.check->add_option("dir", line.check_options.dir, "Recording folder (weft --headless SCENE --out DIR)")
      ->required();

  line.view = app.add_subcommand(
      "view",
      "Open a headless recording in the viewer: scrub and play its frames, its stats.csv plotted, the "
      "strain map and the exact intersection check of the shown frame (the viewer's options apply)");
  line.view->add_option("dir", line.view_dir, "Recording folder (weft --headless SCENE --out DIR)")
      ->required();
  line.view
      ->add_option("--frame", line.view_frame, "The frame shown first (with --screenshot: the one drawn)")
      ->check(whole_number("frame", 0, weft::max_frames, ">= 0"));
  line.view->fallthrough();  // --screenshot, --show, --size, --play... are the viewer's own
}

// weft --headless: the option combinations it refuses, then the run.
int run_headless_command(const CLI::App& app, CommandLine& line) {
  const bool resuming = !line.headless_options.resume_dir.empty();
  if (line.headless_options.out_dir.empty() && !resuming) {
    std::fprintf(stderr, "weft: --headless needs --out DIR, the folder to record into\n");
    return 2;
  }
  if (resuming && !line.headless_options.out_dir.empty() &&
      line.headless_options.out_dir != line.headless_options.resume_dir) {
    std::fprintf(
        stderr,
        "weft: --resume DIR continues the recording in DIR; leave out --out or give the same folder\n");
    return 2;
  }
  for (const char* option :
       {"--screenshot", "--record", "--play", "--quit-after", "--frame-times", "--history-mb"}) {
    if (app.count(option) > 0) {
      std::fprintf(stderr, "weft: %s needs the viewer; it cannot be combined with --headless\n", option);
      return 2;
    }
  }
  line.headless_options.scene_given = app.count("scene") > 0;
  weft::recording_format_from_string(line.format, line.headless_options.format);
  line.headless_options.format_given = app.count("--format") > 0;
  return weft::run_headless(line.headless_options);
}

// The viewer (or, in a build without it, a bad scene reported and the headless command named).
int run_viewer_command(const CLI::App& app, CommandLine& line) {
  for (const char* option : {"--resume", "--checkpoint-every", "--format", "--newton-log"}) {
    if (app.count(option) > 0) {
      std::fprintf(stderr, "weft: %s needs --headless\n", option);
      return 2;
    }
  }
#ifdef WEFT_HAS_VIEWER
  weft::ViewerOptions options;
  options.scene_path = line.headless_options.scene_path;
  if (line.view->parsed()) {
    for (const char* option : {"--set", "--frames", "scene"}) {
      if (app.count(option) > 0) {
        std::fprintf(stderr, "weft view: %s does not apply: a recording is shown as it was run\n", option);
        return 2;
      }
    }
    options.recording_dir = line.view_dir;
    options.recording_frame = line.view_frame;
  }
  options.overrides = line.headless_options.overrides;
  options.screenshot_path = line.screenshot;
  options.frames = line.headless_options.frames < 0 ? 0 : line.headless_options.frames;
  options.record_dir = line.record_dir;
  options.show = line.show;
  options.open_panels = line.open_panels;
  options.box_depth = line.box_depth;
  options.subdivision = line.subdivision;
  options.test_contacts = line.test_contacts;
  options.play = line.play;
  options.history_mb = line.history_mb;
  options.quit_after_seconds = line.quit_after;
  options.frame_times_path = line.frame_times;
  options.threads = line.headless_options.threads;
  parse_window_size(line.window_size_text, options.width, options.height);
  return weft::run_viewer(options);
#else
  // As in a viewer build, a bad scene is reported (exit 2) before anything else.
  try {
    weft::load_scene_file(line.headless_options.scene_path, line.headless_options.overrides);
  } catch (const weft::SceneError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 2;
  }
  std::fprintf(stderr,
               "weft: this build has no viewer (built with WEFT_VIEWER=OFF); run headless instead:\n"
               "  weft --headless %s --out DIR\n",
               line.headless_options.scene_path.c_str());
  return 1;
#endif
}

int run(int argc, char** argv) {
  CLI::App app{"Weft: cloth and soft-body simulation"};
  CommandLine line;
  line.headless_options.scene_path = "scenes/default.json";
  add_run_options(app, line);
  add_subcommands(app, line);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    app.exit(error);
    return 2;
  }

  if (line.version) {
    std::printf("weft %s (%s)\n", weft::version_string, weft::git_commit);
    return 0;
  }
  if (line.sweep->parsed()) return weft::run_sweep(line.sweep_options);
  if (line.plot->parsed()) return weft::run_plot(line.plot_options);
  if (line.check->parsed()) return weft::run_check(line.check_options);
  if (line.view->parsed() && line.headless) {
    std::fprintf(stderr, "weft view: --headless does not apply: view opens a window on a recording\n");
    return 2;
  }
  if (line.headless) return run_headless_command(app, line);
  return run_viewer_command(app, line);
}

void report_out_of_memory() {
  std::fprintf(stderr,
               "weft: out of memory: the scene needs more memory than this process may use "
               "(a smaller grid resolution, fewer cloths, or a machine or job with more memory)\n");
}

std::terminate_handler default_terminate = nullptr;

// std::bad_alloc thrown inside an OpenMP parallel region cannot reach main (the region ends in
// std::terminate): it still gets the out-of-memory message and exit 2 instead of an abort.
[[noreturn]] void terminate_on_out_of_memory() {
  if (const std::exception_ptr error = std::current_exception()) {
    try {
      std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
      report_out_of_memory();
      std::_Exit(2);
    } catch (...) {
    }
  }
  default_terminate();
  std::abort();
}

}  // namespace

int main(int argc, char** argv) {
  weft::prefer_sleeping_openmp_waits(argv);
  default_terminate = std::set_terminate(terminate_on_out_of_memory);
  // Out of memory on the main thread ends here, whole: the output lock is released on the way.
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    report_out_of_memory();
    return 2;
  }
}
