#include "app/sweep_status.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/output_lock.hpp"
#include "io/point_cache.hpp"
#include "io/scene_file.hpp"

namespace weft {

namespace {

namespace fs = std::filesystem;

nlohmann::json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  return in ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json();
}

// Whole rows of stats.csv after its header (frames 0..rows-1); -1 when there is no file.
int stats_rows(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return -1;
  int lines = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && !in.eof()) ++lines;  // a last line without its newline is unfinished
  }
  return lines > 0 ? lines - 1 : 0;
}

// The frame of the case's checkpoint: -1 when there is none, -2 when it cannot be read.
int checkpoint_frame(const fs::path& path) {
  if (!fs::exists(path)) return -1;
  try {
    return read_checkpoint(path.string()).frame;
  } catch (const IoError&) {
    return -2;
  }
}

// "12 s", "4 min", "3 h": how long ago a file was last written.
std::string age_of(const fs::path& path) {
  std::error_code error;
  const auto written = fs::last_write_time(path, error);
  if (error) return "";
  const auto seconds =
      std::chrono::duration_cast<std::chrono::seconds>(fs::file_time_type::clock::now() - written).count();
  if (seconds < 120) return std::to_string(std::max<long long>(0, seconds)) + " s";
  if (seconds < 7200) return std::to_string(seconds / 60) + " min";
  return std::to_string(seconds / 3600) + " h";
}

std::string last_line_of(const fs::path& path) {
  std::ifstream in(path);
  std::string last;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) last = line;
  }
  return last;
}

// Empty when every file of a recording said complete holds frames 0..frames; else what does not.
std::string recording_mismatch(const fs::path& case_dir, const std::string& format, int frames, int rows,
                               int frames_written) {
  const int expected = frames + 1;
  const std::string of = " of " + std::to_string(expected);
  if (frames_written != expected) return "run.json counts " + std::to_string(frames_written) + " frames" + of;
  if (rows != expected) {
    return rows < 0 ? std::string("stats.csv is missing")
                    : "stats.csv holds " + std::to_string(rows) + " frames" + of;
  }
  if (format != "obj") {
    const nlohmann::json manifest = read_json_file(case_dir / "recording.json");
    if (!manifest.is_object() || !manifest.contains("cloths") || !manifest["cloths"].is_array()) {
      return "recording.json is missing or unreadable";
    }
    for (const nlohmann::json& cloth : manifest["cloths"]) {
      const std::string cache = cloth.value("point_cache", std::string());
      try {
        const int samples = point_cache_samples((case_dir / cache).string());
        if (samples != expected) return cache + " holds " + std::to_string(samples) + " frames" + of;
      } catch (const IoError& error) {
        return error.what();
      }
    }
  }
  if (format != "pc2") {
    int files = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(case_dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".obj" &&
          name.find(".tmp.") == std::string::npos) {
        ++files;
      }
    }
    if (files != expected) return std::to_string(files) + " frame_*.obj files" + of;
  }
  return "";
}

// "diverged in frame 12: <message>", from summary.json's failure when it has one.
std::string failure_of(const fs::path& case_dir, const std::string& status) {
  const nlohmann::json summary = read_json_file(case_dir / "summary.json");
  std::string text = status;
  if (summary.is_object() && summary.contains("failure") && summary["failure"].is_object()) {
    const nlohmann::json& failure = summary["failure"];
    if (failure.contains("frame") && failure["frame"].is_number_integer()) {
      text += " in frame " + std::to_string(failure["frame"].get<int>());
    }
    if (failure.contains("message") && failure["message"].is_string()) {
      text += ": " + failure["message"].get<std::string>();
    }
  }
  return text;
}

}  // namespace

RecordedCase recorded_case(const fs::path& case_dir, const nlohmann::json& scene, const std::string& format) {
  const nlohmann::json run = read_json_file(case_dir / "run.json");
  RecordedCase recorded;
  if (!run.is_object()) return recorded;
  if (run.contains("status") && run["status"].is_string()) recorded.status = run["status"].get<std::string>();
  if (run.contains("frames_written") && run["frames_written"].is_number_integer()) {
    recorded.frames_written = run["frames_written"].get<int>();
  }
  // The resolved scene covers the overrides, the sweep's frames and edits to the scene file. A
  // case asking for other frames only may go on from its checkpoint; any other change may not.
  // The view is the viewer's only and not compared.
  nlohmann::json recorded_scene = run.value("scene", nlohmann::json::object());
  nlohmann::json wanted_scene = simulated_part(scene);
  if (recorded_scene.is_object()) recorded_scene = simulated_part(recorded_scene);
  recorded.frames_changed = recorded_scene.value("frames", -1) != wanted_scene.value("frames", -1);
  if (recorded_scene.is_object()) recorded_scene.erase("frames");
  wanted_scene.erase("frames");
  if (recorded_scene != wanted_scene) {
    const nlohmann::json patch = nlohmann::json::diff(recorded_scene, wanted_scene);
    recorded.change =
        "the scene differs at " + (patch.empty() ? std::string("/") : patch[0].value("path", "/"));
  } else if (run.value("format", "") != format) {
    recorded.change =
        "it was recorded as " + run.value("format", std::string("?")) + ", the sweep asks for " + format;
  }
  return recorded;
}

const char* to_string(CaseState state) {
  switch (state) {
    case CaseState::complete:
      return "complete";
    case CaseState::running:
      return "running";
    case CaseState::interrupted:
      return "interrupted";
    case CaseState::failed:
      return "failed";
    case CaseState::changed:
      return "changed";
    case CaseState::not_started:
      break;
  }
  return "not started";
}

CaseStatus case_status(const fs::path& case_dir, const nlohmann::json& scene, const std::string& format) {
  const int frames = scene.value("frames", 0);
  const std::string of_frames = " of " + std::to_string(frames);
  CaseStatus status;
  if (!fs::is_directory(case_dir)) return status;
  const int rows = stats_rows(case_dir / "stats.csv");

  // A live lock: a run writes there now. A lock of another host cannot be checked from here.
  std::ifstream lock_in(case_dir / output_lock_file);
  if (lock_in) {
    std::stringstream text;
    text << lock_in.rdbuf();
    const LockHolder holder = parse_lock_holder(text.str());
    if (holder.pid > 0 && !lock_holder_is_dead(holder)) {
      const bool here = holder.host == this_process().host;
      status.state = CaseState::running;
      status.detail = "on " + holder.host + ", pid " + std::to_string(holder.pid) +
                      (here ? "" : " (another host: not checked)");
      if (rows > 0) {
        status.detail += ": frame " + std::to_string(rows - 1) + of_frames + ", written " +
                         age_of(case_dir / "stats.csv") + " ago";
      } else {
        status.detail += ": starting";
      }
      return status;
    }
  }

  const RecordedCase recorded = recorded_case(case_dir, scene, format);
  if (recorded.status.empty()) {
    // A case that did not get as far as run.json; its log may say why (a held folder, a bad scene).
    const std::string line = last_line_of(case_dir / "log.txt");
    if (!line.empty()) status.detail = "(log.txt: " + line + ")";
    return status;
  }
  const int checkpoint = checkpoint_frame(case_dir / "checkpoint.bin");
  const std::string resumes = "resumable from its checkpoint at frame " + std::to_string(checkpoint);

  // The next sweep's decision (app/sweep.cpp): a case changed in its frames only goes on from a
  // checkpoint that is not past the new end; any other change starts it again.
  if (!recorded.change.empty() || recorded.frames_changed) {
    status.state = CaseState::changed;
    status.resumable = recorded.change.empty() && checkpoint >= 0 && recorded.frames_written - 1 <= frames;
    status.detail = "since it ran (" +
                    (recorded.change.empty() ? "the scene differs at /frames" : recorded.change) + "); " +
                    (status.resumable ? resumes : std::string("the next sweep runs it again"));
    return status;
  }
  if (recorded.status == "complete") {
    const std::string mismatch = recording_mismatch(case_dir, format, frames, rows, recorded.frames_written);
    if (mismatch.empty()) {
      status.state = CaseState::complete;
      status.detail = "(frames 0.." + std::to_string(frames) + ")";
    } else {
      status.state = CaseState::failed;
      status.detail = "run.json says complete, but " + mismatch + "; the next sweep runs it again";
    }
    return status;
  }
  if (recorded.status == "running" || recorded.status == "interrupted") {
    // "running" with no live lock: the process was killed (SIGKILL, a lost node) without a word.
    status.state = CaseState::interrupted;
    status.resumable = checkpoint >= 0;
    status.detail = std::string(recorded.status == "running" ? "(killed) " : "") + "after frame " +
                    std::to_string(std::max(rows, recorded.frames_written) - 1) + of_frames + "; " +
                    (checkpoint >= 0    ? resumes
                     : checkpoint == -2 ? "not resumable: checkpoint.bin is damaged"
                                        : "not resumable: no checkpoint, the next sweep starts it again");
    return status;
  }
  status.state = CaseState::failed;
  status.detail = failure_of(case_dir, recorded.status);
  return status;
}

int print_sweep_status(const SweepDesc& sweep, const std::vector<SweepCase>& cases,
                       const std::vector<nlohmann::json>& case_scenes, const fs::path& out) {
  size_t width = 0;
  for (const SweepCase& sweep_case : cases) width = std::max(width, sweep_case.name.size());
  std::map<CaseState, int> counts;
  int resumable = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const CaseStatus status = case_status(out / cases[i].name, case_scenes[i], sweep.format);
    ++counts[status.state];
    if (status.state == CaseState::interrupted && status.resumable) ++resumable;
    std::printf("%-*s  %s%s%s\n", static_cast<int>(width), cases[i].name.c_str(), to_string(status.state),
                status.detail.empty() ? "" : " ", status.detail.c_str());
  }
  // "drape: 3 of 8 complete, 1 running, 2 interrupted (1 resumable), 1 failed, 1 not started"
  std::printf("%s: %d of %zu complete", sweep.name.c_str(), counts[CaseState::complete], cases.size());
  for (const CaseState state : {CaseState::running, CaseState::interrupted, CaseState::failed,
                                CaseState::changed, CaseState::not_started}) {
    if (counts[state] == 0) continue;
    std::printf(", %d %s", counts[state], to_string(state));
    if (state == CaseState::interrupted) std::printf(" (%d resumable)", resumable);
  }
  std::printf("; in %s\n", out.c_str());
  if (counts[CaseState::complete] == static_cast<int>(cases.size())) return 0;
  return counts[CaseState::failed] > 0 ? 5 : 1;
}

}  // namespace weft
