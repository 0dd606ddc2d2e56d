#pragma once
// Where each case of a sweep stands, read from its folder alone (run.json, summary.json, the
// recording, stats.csv, checkpoint.bin and the case's .weft.lock), so that `weft sweep FILE
// --status` works the same for a local sweep and for a SLURM array writing on a shared disk.
// The local sweep decides from the same reading which cases to skip.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/sweep_file.hpp"

namespace weft {

// What a case folder's run.json says about the run recorded there, against the case as the
// sweep defines it now.
struct RecordedCase {
  std::string status;  // "complete", "interrupted", ...; empty if there is no run.json
  int frames_written = 0;
  std::string change;  // empty when recorded with this case's scene (frames aside) and format
  bool frames_changed = false;
};

RecordedCase recorded_case(const std::filesystem::path& case_dir, const nlohmann::json& scene,
                           const std::string& format);

enum class CaseState { complete, running, interrupted, failed, changed, not_started };
const char* to_string(CaseState state);

struct CaseStatus {
  CaseState state = CaseState::not_started;
  std::string detail;      // the rest of the status line, e.g. "on node3, pid 812: frame 37 of 100"
  bool resumable = false;  // interrupted (or changed in its frames only) with a checkpoint to resume from
};

// One case's folder read against the case's resolved scene and the sweep's format. A case is
// complete only when run.json says so, its definition is unchanged, and run.json, stats.csv and
// every recorded file hold frames 0..frames.
CaseStatus case_status(const std::filesystem::path& case_dir, const nlohmann::json& scene,
                       const std::string& format);

// `weft sweep FILE --status`: one line per case and a summary line on stdout. Returns 0 when
// every case is complete, 5 when some case failed, 1 otherwise (cases still to run or running).
int print_sweep_status(const SweepDesc& sweep, const std::vector<SweepCase>& cases,
                       const std::vector<nlohmann::json>& case_scenes, const std::filesystem::path& out);

}  // namespace weft
