#include "app/headless_runner.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "app/progress.hpp"
#include "app/world_tangles.hpp"
#include "core/error.hpp"
#include "core/phase_timer.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/csv_log.hpp"
#include "io/output_lock.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "weft/version.hpp"

namespace weft {

namespace {

namespace fs = std::filesystem;
using Clock = PhaseClock;

constexpr const char* checkpoint_file = "checkpoint.bin";
// --newton-log: one row per Newton iteration of every implicit Euler step (docs/recording.md).
constexpr const char* newton_log_file = "newton.csv";
constexpr const char* newton_log_header =
    "frame,step,substep,cloth,iteration,residual,above_tolerance,step_scale,linear_iterations,"
    "restricted_iterations";
constexpr const char* stats_header =
    "frame,time,kinetic_energy,potential_energy,gravitational_energy,elastic_energy,spring_energy,"
    "membrane_energy,bending_energy,pressure_energy,energy_dissipated,contacts,newton_iterations,"
    "linear_iterations,accepted_steps,rejected_steps,yielded_triangles,prepare_collisions_ms,integrate_ms,"
    "collisions_ms,rest_update_ms,record_ms,wall_ms,steps,broad_phase_ms,narrow_phase_ms,response_ms,step_ms,"
    "vertex_face_candidates,edge_edge_candidates,proximity_contacts,ccd_impulses,impact_zone_vertices,"
    "collisions_clean,strain_limited_edges,newton_residual,unconverged_steps,external_work,dissipated_"
    "damping,"
    "dissipated_integrator,dissipated_contact,dissipated_plastic,budget_error,threads,held_pins,"
    "edges_over_strain_limit,collision_correction_max,collision_corrected_vertices,dissipated_residual,"
    "substeps,intersecting_pairs,vertices_inside_colliders,check_ms,untangled_vertices,untangle_ms";

volatile std::sig_atomic_t stop_requested = 0;
extern "C" void request_stop(int) { stop_requested = 1; }

// Ctrl-C and SIGTERM (a cluster's time limit) finish the frame in progress and stop.
void install_stop_handlers() {
  stop_requested = 0;
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// `flows` are summed from frame 0; budget_error = energy now + dissipated - energy at frame 0 -
// external work (sim/energy_ledger.hpp).
std::string stats_line(int frame, double time, const Energies& e, double initial_energy,
                       const EnergyFlows& flows, const StepStats& s, const TangleReport& tangles,
                       double check_ms, double record_ms, double wall_ms) {
  const double dissipated = flows.dissipated();
  const double budget_error = e.total() + dissipated - initial_energy - flows.external_work;
  std::ostringstream out;
  out << std::setprecision(10) << frame << ',' << time << ',' << e.kinetic << ','
      << e.gravitational + e.elastic << ',' << e.gravitational << ',' << e.elastic << ',' << e.terms.springs
      << ',' << e.terms.membrane << ',' << e.terms.bending << ',' << e.terms.pressure << ',' << dissipated
      << ',' << s.contacts << ',' << s.newton_iterations << ',' << s.linear_iterations << ','
      << s.accepted_steps << ',' << s.rejected_steps << ',' << s.yielded_triangles << ','
      << s.prepare_collisions_ms << ',' << s.integrate_ms << ',' << s.collisions_ms << ',' << s.rest_update_ms
      << ',' << record_ms << ',' << wall_ms << ',' << s.steps << ',' << s.collision.broad_ms << ','
      << s.collision.narrow_ms << ',' << s.collision.response_ms << ',' << s.total_ms << ','
      << s.collision.vertex_face_candidates << ',' << s.collision.edge_edge_candidates << ','
      << s.collision.proximity_contacts << ',' << s.collision.ccd_impulses << ','
      << s.collision.impact_zone_vertices << ',' << (s.collision.clean ? 1 : 0) << ','
      << s.collision.strain_limited_edges << ',' << s.residual << ',' << s.unconverged_steps << ','
      << flows.external_work << ',' << flows.damping << ',' << flows.integrator << ',' << flows.contact << ','
      << flows.plastic << ',' << budget_error << ','
      << (s.steps > 0 ? static_cast<double>(s.thread_steps) / s.steps : 0.0) << ',' << s.collision.held_pins
      << ',' << s.collision.edges_over_strain_limit << ',' << s.collision.largest_correction << ','
      << s.collision.corrected_vertices << ',' << flows.residual << ',' << s.substeps << ','
      << tangles.intersecting_pairs << ',' << tangles.vertices_inside_colliders << ',' << check_ms << ','
      << s.untangled_vertices << ',' << s.untangle_ms;
  return out.str();
}

// The per-run summary, computed from the stats rows (so a resumed run covers all its frames).
nlohmann::json summarise(const std::vector<std::string>& rows, const std::string& status, int exit_code,
                         int frames_requested) {
  std::vector<std::string> columns;
  {
    std::stringstream header(stats_header);
    for (std::string name; std::getline(header, name, ',');) columns.push_back(name);
  }
  const auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
  };
  std::vector<std::vector<double>> table;
  for (const std::string& row : rows) {
    std::vector<double> values;
    std::stringstream fields(row);
    for (std::string field; std::getline(fields, field, ',');)
      values.push_back(std::strtod(field.c_str(), nullptr));
    if (values.size() == columns.size()) table.push_back(values);
  }
  double wall = 0.0, wall_max = 0.0, newton = 0.0, newton_max = 0.0, contacts_max = 0.0;
  double unconverged = 0.0, residual_max = 0.0, budget_error_max = 0.0, held_pins = 0.0, over_limit = 0.0;
  double correction_max = 0.0, pairs_max = 0.0, inside_max = 0.0;
  for (const std::vector<double>& row : table) {  // frame 0 too: a tangled start
    pairs_max = std::max(pairs_max, row[column("intersecting_pairs")]);
    inside_max = std::max(inside_max, row[column("vertices_inside_colliders")]);
  }
  for (size_t r = 1; r < table.size(); ++r) {  // frame 0 is the initial state, not simulated
    wall += table[r][column("wall_ms")];
    wall_max = std::max(wall_max, table[r][column("wall_ms")]);
    newton += table[r][column("newton_iterations")];
    newton_max = std::max(newton_max, table[r][column("newton_iterations")]);
    contacts_max = std::max(contacts_max, table[r][column("contacts")]);
    unconverged += table[r][column("unconverged_steps")];
    held_pins += table[r][column("held_pins")];
    over_limit += table[r][column("edges_over_strain_limit")];
    correction_max = std::max(correction_max, table[r][column("collision_correction_max")]);
    residual_max = std::max(residual_max, table[r][column("newton_residual")]);
    budget_error_max = std::max(budget_error_max, std::abs(table[r][column("budget_error")]));
  }
  const int simulated = table.empty() ? 0 : static_cast<int>(table.size()) - 1;
  nlohmann::json summary = {
      {"status", status},
      {"exit_code", exit_code},
      {"frames_requested", frames_requested},
      {"frames_written", table.size()},
      {"wall_seconds", wall / 1000.0},
      {"ms_per_frame", {{"mean", simulated > 0 ? wall / simulated : 0.0}, {"max", wall_max}}},
      {"newton_iterations", {{"total", newton}, {"max_per_frame", newton_max}}},
      {"unconverged_steps", unconverged},
      {"newton_residual_max", residual_max},
      {"held_pins", held_pins},
      {"edges_over_strain_limit", over_limit},
      {"collision_correction_max", correction_max},
      {"contacts_max", contacts_max}};
  if (!table.empty()) {
    const std::vector<double>& first = table.front();
    const std::vector<double>& last = table.back();
    summary["simulated_seconds"] = last[column("time")];
    const auto count = [](double value) { return static_cast<long long>(value); };
    summary["tangles"] = {
        {"first_frame",
         {{"intersecting_pairs", count(first[column("intersecting_pairs")])},
          {"vertices_inside_colliders", count(first[column("vertices_inside_colliders")])}}},
        {"max",
         {{"intersecting_pairs", count(pairs_max)}, {"vertices_inside_colliders", count(inside_max)}}}};
    summary["energy"] = {
        {"initial_total", first[column("kinetic_energy")] + first[column("potential_energy")]},
        {"final_kinetic", last[column("kinetic_energy")]},
        {"final_potential", last[column("potential_energy")]},
        {"dissipated", last[column("energy_dissipated")]},
        {"external_work", last[column("external_work")]},
        {"dissipated_by", {{"damping", last[column("dissipated_damping")]},
                           {"integrator", last[column("dissipated_integrator")]},
                           {"contact", last[column("dissipated_contact")]},
                           {"plastic", last[column("dissipated_plastic")]},
                           {"residual", last[column("dissipated_residual")]}}},
        {"budget_error_max", budget_error_max}};
  }
  return summary;
}

// A checkpoint's scene as this version writes it, so that keys added since the checkpoint was
// written compare at their defaults (a checkpoint from before `bending.model` ran the dihedral
// model, which is the default). A scene this version cannot read is compared as written.
nlohmann::json in_current_form(const nlohmann::json& scene, const std::string& source) {
  try {
    return scene_to_json(parse_scene(scene, source));
  } catch (const SceneError&) {
    return scene;
  }
}

// A scene as its resolved JSON without "frames", which a resumed run may change.
nlohmann::json comparable_scene(nlohmann::json scene) {
  scene = simulated_part(std::move(scene));
  scene.erase("frames");
  return scene;
}

class Run {
 public:
  explicit Run(const HeadlessOptions& options) : options_(options) {}
  int execute();

 private:
  int load();
  int record_and_step();
  void open_outputs(RecordingWriter& recording);
  void record_frame(int frame, const StepStats& steps, Clock::time_point frame_start, RecordingWriter& recording,
                    WorldTangles& tangles);
  Instability step_frame(int frame, const FrameSchedule& schedule, ProgressReporter& progress,
                         StepStats& frame_steps);
  int stop_diverged(int frame, const Instability& problem, const StepStats& frame_steps, ProgressReporter& progress);
  int finish_run();
  void write_run_json(const std::string& status) const;
  void write_summary(const std::string& status, int exit_code, const nlohmann::json& failure = nullptr) const;
  void write_checkpoint_now(int frame) const;
  void say_replacing_a_run() const;

  const HeadlessOptions& options_;
  RecordingFormat format_ = RecordingFormat::point_cache;  // --format, or on resume the recorded one
  std::vector<std::string> overrides_;  // as given, plus "frames=N" for --frames
  std::string scene_file_;
  SceneDesc scene_;
  std::string scene_json_;
  World world_;
  fs::path out_;
  int first_frame_ = 0;  // the frame to record first (0, or the checkpoint's + 1)
  int frames_written_ = 0;
  double initial_energy_ = 0.0;
  EnergyFlows energy_flows_;             // summed from frame 0
  std::vector<std::string> stats_rows_;  // every stats.csv row so far, for summary.json
  CsvLog stats_log_;
  bool log_newton_ = false;  // --newton-log, or resuming a run that kept one
  CsvLog newton_log_;
  std::string newton_rows_;  // the current frame's newton.csv rows, appended with it
  void add_newton_rows(int frame, int step);
  void flush_newton_rows();
  Checkpoint checkpoint_;
};

// Reads and checks everything (scene, checkpoint) before touching the output folder.
int Run::load() {
  const bool resuming = !options_.resume_dir.empty();
  format_ = options_.format;
  out_ = resuming ? fs::path(options_.resume_dir) : fs::path(options_.out_dir);
  scene_file_ = options_.scene_path;
  overrides_ = options_.overrides;
  if (resuming) {
    const std::string checkpoint_path = (out_ / checkpoint_file).string();
    if (!fs::exists(checkpoint_path)) {
      std::fprintf(
          stderr, "weft: %s: no checkpoint to resume from (was the run started with --checkpoint-every N?)\n",
          checkpoint_path.c_str());
      return exit_bad_input;
    }
    checkpoint_ = read_checkpoint(checkpoint_path);
    const std::string run_path = (out_ / "run.json").string();
    std::ifstream in(run_path);
    const nlohmann::json run = nlohmann::json::parse(in, nullptr, false);
    // The recording goes on in the format it started in: frames of another would mix in one folder.
    RecordingFormat recorded_format;
    if (run.is_object() && run.contains("format") && run["format"].is_string() &&
        recording_format_from_string(run["format"].get<std::string>(), recorded_format)) {
      if (!options_.format_given) {
        format_ = recorded_format;
      } else if (format_ != recorded_format) {
        std::fprintf(stderr,
                     "weft: %s: the run was recorded with --format %s; resume it with --format %s (or "
                     "without --format), not %s\n",
                     run_path.c_str(), to_string(recorded_format), to_string(recorded_format),
                     to_string(format_));
        return exit_bad_input;
      }
    }
    if (!options_.scene_given) {
      // The recorded run's scene file and overrides, as run.json has them.
      if (run.is_discarded() || !run.contains("scene_file") || !run["scene_file"].is_string() ||
          !run.contains("overrides") || !run["overrides"].is_array()) {
        std::fprintf(stderr,
                     "weft: %s: expected the recorded run's \"scene_file\" and \"overrides\"; "
                     "name the scene on the command line instead\n",
                     run_path.c_str());
        return exit_bad_input;
      }
      scene_file_ = run["scene_file"].get<std::string>();
      std::vector<std::string> recorded = run["overrides"].get<std::vector<std::string>>();
      recorded.insert(recorded.end(), overrides_.begin(), overrides_.end());
      overrides_ = recorded;
    }
  }
  if (options_.frames >= 0) overrides_.push_back("frames=" + std::to_string(options_.frames));
  scene_ = load_scene_file(scene_file_, overrides_);
  try {
    world_ = build_world(scene_);
  } catch (const SceneError& error) {
    throw naming_override(error, overrides_);
  }
  world_.settings.threads = options_.threads > 0 ? options_.threads : omp_get_num_procs();
  world_.settings.adapt_threads = !options_.fixed_threads;
  // A resumed run goes on with the log its first part kept.
  log_newton_ = options_.newton_log || (!options_.resume_dir.empty() && fs::exists(out_ / newton_log_file));
  world_.settings.implicit.record_iterations = log_newton_;
  scene_json_ = scene_to_json(scene_).dump();
  if (resuming) {
    const nlohmann::json saved = comparable_scene(
        in_current_form(nlohmann::json::parse(checkpoint_.scene_json), (out_ / checkpoint_file).string()));
    const nlohmann::json now = comparable_scene(nlohmann::json::parse(scene_json_));
    if (saved != now) {
      const nlohmann::json patch = nlohmann::json::diff(saved, now);
      const std::string where = patch.empty() ? "/" : patch[0].value("path", "/");
      const nlohmann::json::json_pointer pointer(where);
      std::fprintf(stderr,
                   "weft: %s: the scene differs from the checkpoint's at %s (checkpoint: %s, now: %s); "
                   "resume with the same scene and overrides\n",
                   (out_ / checkpoint_file).c_str(), where.c_str(),
                   saved.contains(pointer) ? saved[pointer].dump().c_str() : "absent",
                   now.contains(pointer) ? now[pointer].dump().c_str() : "absent");
      return exit_bad_input;
    }
    if (checkpoint_.frame > scene_.frames) {
      std::fprintf(stderr, "weft: %s: the checkpoint is at frame %d, past the %d frames asked for\n",
                   (out_ / checkpoint_file).c_str(), checkpoint_.frame, scene_.frames);
      return exit_bad_input;
    }
    restore_checkpoint(checkpoint_, world_, (out_ / checkpoint_file).string());
    first_frame_ = checkpoint_.frame + 1;
    initial_energy_ = checkpoint_.initial_energy;
    energy_flows_ = checkpoint_.energy_flows;
  } else {
    initial_energy_ = world_.energies().total();
  }
  return exit_done;
}

void Run::write_run_json(const std::string& status) const {
  const nlohmann::json run = {{"weft_version", version_string},
                              {"git_commit", git_commit},
                              {"scene_file", scene_file_},
                              {"overrides", overrides_},
                              {"threads", world_.settings.threads},
                              {"format", to_string(format_)},
                              {"checkpoint_every", options_.checkpoint_every},
                              {"status", status},
                              {"frames_written", frames_written_},
                              {"scene", nlohmann::json::parse(scene_json_)}};
  write_file_atomically((out_ / "run.json").string(), [&](std::ostream& out) { out << run.dump(2) << '\n'; });
}

void Run::write_summary(const std::string& status, int exit_code, const nlohmann::json& failure) const {
  nlohmann::json summary = summarise(stats_rows_, status, exit_code, scene_.frames);
  if (!failure.is_null()) summary["failure"] = failure;
  write_file_atomically((out_ / "summary.json").string(),
                        [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
}

void Run::write_checkpoint_now(int frame) const {
  write_checkpoint((out_ / checkpoint_file).string(),
                   capture_checkpoint(world_, frame, scene_json_, initial_energy_, energy_flows_));
}

int Run::execute() {
  try {
    if (const int code = load(); code != exit_done) return code;
  } catch (const SceneError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return exit_bad_input;
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return exit_bad_input;
  }

  // Held until this function returns, on every path: one writer per output folder.
  OutputLock lock;
  try {
    std::error_code error;
    fs::create_directories(out_, error);
    if (error || !fs::is_directory(out_)) {
      throw IoError(out_.string() + ": cannot create output folder" + (error ? ": " + error.message() : ""));
    }
    lock = OutputLock(out_);
    if (!lock.took_over().empty()) std::fprintf(stderr, "weft: %s\n", lock.took_over().c_str());
    return record_and_step();
  } catch (const OutputLocked& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return exit_bad_input;
  } catch (const IoError& error) {
    if (!lock.held()) {
      std::fprintf(stderr, "weft: %s\n", error.what());
      return exit_output_error;
    }
    std::fprintf(stderr, "weft: %s\n", error.what());
    // Best effort: say in run.json why the run stopped (this may fail too when the disk is full).
    try {
      write_run_json("output_error");
      write_summary("output_error", exit_output_error, {{"message", error.what()}});
    } catch (const IoError&) {
    }
    return exit_output_error;
  }
}

// The last step's Newton iterations as newton.csv rows (newton_log_header), kept until the frame
// is recorded.
void Run::add_newton_rows(int frame, int step) {
  char row[256];
  for (const World::NewtonLogRow& entry : world_.newton_log()) {
    const NewtonIterationRecord& r = entry.record;
    std::snprintf(row, sizeof row, "%d,%d,%d,%d,%d,%.6g,%d,%.6g,%d,%d\n", frame, step, entry.substep, entry.cloth,
                  entry.iteration, r.residual, r.above_tolerance, r.step_scale, r.linear_iterations,
                  r.restricted_iterations);
    newton_rows_ += row;
  }
}

// Appends the rows kept since the last frame was recorded (none: nothing).
void Run::flush_newton_rows() {
  if (newton_rows_.empty()) return;
  newton_rows_.pop_back();  // the last row's newline: append adds it
  newton_log_.append(newton_rows_);
  newton_rows_.clear();
}

// A new run into a folder that holds another's: said, so that nobody takes it for a resume. Called
// before the folder's files are replaced (its run.json says what ran there).
void Run::say_replacing_a_run() const {
  const fs::path run_path = out_ / "run.json";
  std::error_code error;
  if (!fs::exists(run_path, error) && !fs::exists(out_ / "stats.csv", error)) return;
  std::ifstream in(run_path);
  const nlohmann::json run = nlohmann::json::parse(in, nullptr, false);
  std::string what = "an earlier run";
  if (run.is_object() && run.contains("status") && run["status"].is_string() &&
      run.contains("frames_written") && run["frames_written"].is_number_integer()) {
    what += " (" + run["status"].get<std::string>() + ", " +
            std::to_string(run["frames_written"].get<long long>()) + " frames written)";
  }
  std::fprintf(stderr, "weft: %s: replacing %s; --resume %s continues a run instead\n", out_.c_str(),
               what.c_str(), out_.c_str());
}

// The recording, stats.csv and newton.csv opened: created for a new run (an earlier run's files
// replaced), or reopened at the checkpoint's frame for a resumed one.
void Run::open_outputs(RecordingWriter& recording) {
  std::error_code ignored;
  // summary.json is written at the end: one left from an earlier run, or from the first part of
  // this one, would speak for this run until then, and for ever if it is killed.
  fs::remove(out_ / "summary.json", ignored);
  if (first_frame_ == 0) {
    say_replacing_a_run();
    fs::remove(out_ / checkpoint_file, ignored);  // a stale checkpoint of an earlier run
    if (!log_newton_) fs::remove(out_ / newton_log_file, ignored);
    write_run_json("running");
    recording.start(world_);
    stats_log_ = CsvLog::create((out_ / "stats.csv").string(), stats_header);
    if (log_newton_) newton_log_ = CsvLog::create((out_ / newton_log_file).string(), newton_log_header);
  } else {
    frames_written_ = first_frame_;
    stats_log_ = CsvLog::reopen((out_ / "stats.csv").string(), stats_header, first_frame_ - 1, &stats_rows_);
    if (static_cast<int>(stats_rows_.size()) != first_frame_) {
      throw IoError((out_ / "stats.csv").string() + ": expected the rows of frames 0.." +
                    std::to_string(first_frame_ - 1) + " to resume, found " +
                    std::to_string(stats_rows_.size()));
    }
    if (log_newton_) {
      const std::string path = (out_ / newton_log_file).string();
      newton_log_ = fs::exists(path) ? CsvLog::reopen(path, newton_log_header, first_frame_ - 1)
                                     : CsvLog::create(path, newton_log_header);
    }
    write_run_json("running");
    recording.resume(world_, first_frame_ - 1);
    // Said even with --quiet: a sweep's or a cluster job's log shows where the run went on from.
    std::fprintf(stderr, "weft: resumed from frame %d of %d (%s)\n", first_frame_ - 1, scene_.frames,
                 (out_ / checkpoint_file).c_str());
  }
}

// One frame recorded: the exact tangle check of its state (frame 0's said when tangled), the
// recording, the stats row, the frame's Newton rows and, when due, a checkpoint.
void Run::record_frame(int frame, const StepStats& steps, Clock::time_point frame_start, RecordingWriter& recording,
                       WorldTangles& tangles) {
  // The exact check of the frame's state; frame 0's is said when it is tangled.
  const auto check_start = Clock::now();
  const TangleReport report = tangles.check(world_);
  const double check_ms = milliseconds_since(check_start);
  if (frame == 0) say_if_tangled_at_start(scene_file_, report, tangles.input());
  const auto record_start = Clock::now();
  recording.write_frame(frame, world_);
  const Energies energies = world_.energies();
  const double record_ms = milliseconds_since(record_start);
  energy_flows_ += steps.energy_flows;
  stats_rows_.push_back(stats_line(frame, world_.time(), energies, initial_energy_, energy_flows_, steps,
                                   report, check_ms, record_ms,
                                   frame == 0 ? 0.0 : milliseconds_since(frame_start)));
  stats_log_.append(stats_rows_.back());
  flush_newton_rows();
  frames_written_ = frame + 1;
  if (options_.checkpoint_every > 0 && frame > 0 && frame % options_.checkpoint_every == 0) {
    write_checkpoint_now(frame);
  }
}

// The steps of one frame, each checked for divergence; the first problem stops the frame.
Instability Run::step_frame(int frame, const FrameSchedule& schedule, ProgressReporter& progress,
                            StepStats& frame_steps) {
  Instability problem;
  for (int step = 0; step < schedule.steps_per_frame && !problem.found; ++step) {
    world_.step();
    if (log_newton_) add_newton_rows(frame, step);
    frame_steps += world_.last_step_stats();
    problem = check_state(world_, options_.limits);
    progress.update(frame - 1, step + 1, schedule.steps_per_frame);
  }
  if (!problem.found) problem = check_strain(world_, options_.limits);
  return problem;
}

// A frame that diverged (`problem`) or whose adaptive steps missed their tolerance: said on
// stderr, run.json and summary.json say so; returns the exit code.
int Run::stop_diverged(int frame, const Instability& problem, const StepStats& frame_steps,
                       ProgressReporter& progress) {
  if (!problem.found) {
    progress.finish(frames_written_ - 1);
    // Adaptive stepping reached its smallest step with the error estimate still too large.
      char message[512];
    std::snprintf(message, sizeof message,
                  "adaptive stepping could not meet solver.adaptive.tolerance = %.3g m in frame %d (t = %.6g s): %d "
                  "steps at solver.adaptive.min_step = %.3g s still estimated a larger local error",
                  scene_.adaptive.tolerance, frame, world_.time(), frame_steps.unmet_tolerance_steps,
                  scene_.adaptive.h_min);
    std::fprintf(stderr,
                 "weft: %s. Frames 0..%d are written. Lower min_step, raise the tolerance, or use "
                 "implicit_euler.\n",
                 message, frames_written_ - 1);
    flush_newton_rows();  // the diverging frame's iterations too: what went wrong
    write_run_json("diverged");
    write_summary("diverged", exit_diverged, {{"frame", frame}, {"time", world_.time()}, {"message", message}});
    return exit_diverged;
  }
  progress.finish(frames_written_ - 1);
  std::fprintf(stderr,
               "weft: the simulation diverged in frame %d (t = %.6g s): %s. Frames 0..%d are written%s. "
               "Try a smaller solver.time_step, more solver.substeps or softer springs.\n",
               frame, world_.time(), problem.describe().c_str(), frames_written_ - 1,
               fs::exists(out_ / checkpoint_file) ? " and the last checkpoint is kept" : "");
  flush_newton_rows();  // the diverging frame's iterations too: what went wrong
  write_run_json("diverged");
  write_summary(
      "diverged", exit_diverged,
      {{"frame", frame},
       {"time", world_.time()},
       {"cloth", problem.cloth_name},
       {"vertex", problem.vertex},
       {"quantity", problem.quantity},
       {"element", problem.element >= 0 ? nlohmann::json(problem.element) : nlohmann::json(nullptr)},
       {"value", std::isfinite(problem.value) ? nlohmann::json(problem.value) : nlohmann::json(nullptr)},
       {"term", problem.term},
       {"message", problem.describe()}});
  return exit_diverged;
}

// After the last frame (or a stop): the run's warnings, run.json and summary.json; returns the
// exit code.
int Run::finish_run() {
  // Over the whole run, resumed or not: the figures summary.json gives.
  const nlohmann::json totals = summarise(stats_rows_, "", 0, scene_.frames);
  const int unconverged_steps = totals["unconverged_steps"].get<int>();
  const double worst_residual = totals["newton_residual_max"].get<double>();
  if (unconverged_steps > 0) {
    // The energy the unconverged steps left (the residual's work, booked by the energy ledger).
    const double residual_work =
        totals.contains("energy") ? totals["energy"]["dissipated_by"].value("residual", 0.0) : 0.0;
    std::fprintf(stderr,
                 "weft: %d implicit Euler steps ended unconverged (largest residual %.3g m/s against the "
                 "tolerance %.3g m/s; dissipated_residual %.3g J, negative where they added energy); stats.csv "
                 "has them per frame. Raise solver.newton.max_iterations (now %d) or use "
                 "solver.newton.linear_solver \"cholesky\".\n",
                 unconverged_steps, worst_residual, scene_.implicit.newton_tolerance, residual_work,
                 scene_.implicit.max_newton_iterations);
  }
  const int held_pins = totals["held_pins"].get<int>();
  if (held_pins > 0) {
    std::fprintf(
        stderr,
        "weft: %d times a cloth pin was held at its start of step, lagging its script, because nothing "
        "else kept cloth from passing through cloth (those steps are reported unclean); stats.csv's "
        "held_pins has them per frame. Slow the pins' script down or lower solver.time_step.\n",
        held_pins);
  }
  if (stop_requested) {
    // A checkpoint of the last whole frame, so a preempted cluster job resumes where it stopped.
    if (options_.checkpoint_every > 0 && frames_written_ > 1) write_checkpoint_now(frames_written_ - 1);
    write_run_json("interrupted");
    write_summary("interrupted", exit_interrupted);
    std::fprintf(stderr, "weft: interrupted; frames 0..%d in %s are complete\n", frames_written_ - 1,
                 out_.c_str());
    return exit_interrupted;
  }
  write_run_json("complete");
  write_summary("complete", exit_done);
  return exit_done;
}

int Run::record_and_step() {
  const FrameSchedule schedule = frame_schedule(scene_.fps, scene_.time_step);
  RecordingWriter recording(out_.string(), format_, scene_.frames, scene_.fps);
  open_outputs(recording);
  WorldTangles tangles;
  install_stop_handlers();
  ProgressReporter progress(scene_.frames, !options_.quiet);
  // A resumed run's line counts from the frames already recorded.
  progress.add_unconverged_steps(summarise(stats_rows_, "", 0, scene_.frames)["unconverged_steps"].get<int>());
  if (first_frame_ == 0) record_frame(0, StepStats{}, Clock::now(), recording, tangles);
  for (int frame = std::max(1, first_frame_); frame <= scene_.frames; ++frame) {
    if (stop_requested) break;
    const auto frame_start = Clock::now();
    StepStats frame_steps;
    const Instability problem = step_frame(frame, schedule, progress, frame_steps);
    if (problem.found || frame_steps.unmet_tolerance_steps > 0) {
      return stop_diverged(frame, problem, frame_steps, progress);
    }
    record_frame(frame, frame_steps, frame_start, recording, tangles);
    progress.add_unconverged_steps(frame_steps.unconverged_steps);
    progress.update(frame);
  }
  progress.finish(frames_written_ - 1);
  return finish_run();
}

}  // namespace

int run_headless(const HeadlessOptions& options) {
  Run run(options);
  return run.execute();
}

}  // namespace weft
