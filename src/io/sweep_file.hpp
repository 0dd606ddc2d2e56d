#pragma once
// Sweep files: a scene, common overrides and a grid of overrides whose every combination is one
// named run (docs/sweeps.md). Read with every field checked, like scene files.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace weft {

// Most local runs at once ("jobs", --jobs): each case is a process of its own, and past this
// many a machine spends its time switching between them.
constexpr int max_sweep_jobs = 1024;

// Most cases in one sweep (the product of the grid's value counts). More than a cluster's job
// array runs in a day, and a grid of 40 keys with two values each (2^40 cases) would exhaust the
// memory before its case names were written.
constexpr long long max_sweep_cases = 100000;

// Sweeps checkpoint every this many frames unless the sweep file says otherwise ("checkpoint_every",
// 0 for none), so a case stopped by a time limit, a preemption or a lost node resumes. A stop
// (SIGTERM) also writes one at the frame it ends on whenever this is not 0.
constexpr int default_sweep_checkpoint_every = 10;

struct SlurmSettings {
  std::string partition;            // #SBATCH --partition (empty: the cluster's default)
  std::string time = "01:00:00";    // #SBATCH --time, per case
  std::string memory = "2G";        // #SBATCH --mem, per case
  int max_parallel = 0;             // #SBATCH --array=...%N (0: no limit)
  std::vector<std::string> sbatch;  // further "#SBATCH" options, e.g. "--account=cloth"
};

struct SweepDesc {
  std::string source_file;     // for error messages
  std::string name;            // default: the sweep file's stem
  std::string scene;           // the scene file, resolved against the sweep file's folder
  std::string out;             // the sweep's folder; each case records into out/CASE (default out/NAME)
  int frames = -1;             // -1: the scene's
  int threads = 1;             // solver threads per case
  int jobs = 0;                // local runs at once (0: cores / threads)
  int checkpoint_every = default_sweep_checkpoint_every;  // frames; 0: no checkpoints
  std::string format = "pc2";  // recording format of each case
  std::vector<std::string> overrides;  // "set": applied to every case, before the grid's
  std::vector<std::pair<std::string, std::vector<nlohmann::json>>> grid;  // path -> values, in file order
  SlurmSettings slurm;
};

struct SweepCase {
  std::string name;                    // "002_stiffness-500_mass_damping-0.1"
  std::vector<std::string> overrides;  // common overrides, then this case's "path=value"s
};

// Reads a sweep file; throws SceneError naming the file, the JSON path and what was expected.
SweepDesc load_sweep_file(const std::string& path);

// The same from a sweep file's text; `path` names it in errors and is the folder the scene
// resolves against (load_sweep_file reads the file and calls this).
SweepDesc parse_sweep(const std::string& text, const std::string& path);

// Every combination of the grid's values (the last key varies fastest), named by index and values.
std::vector<SweepCase> expand_sweep(const SweepDesc& sweep);

}  // namespace weft
