#pragma once
// `weft sweep SWEEP.json`: expands a grid of scene overrides into named runs, then either runs
// them locally on a bounded pool of worker processes or (--slurm) writes a SLURM array job
// script that runs one case per array index; --status reads where each case stands.
#include <string>

namespace weft {

struct SweepOptions {
  std::string sweep_file;
  std::string out_dir;   // overrides the sweep file's "out"
  bool slurm = false;    // write the sbatch script instead of running
  int jobs = -1;         // local runs at once (-1: the sweep file's "jobs", 0: cores / threads)
  bool dry_run = false;  // list the cases and exit
  bool status = false;   // say where each case stands (app/sweep_status.hpp) and exit
};

// Exit codes: 0 every case complete (or the script written), 2 bad sweep or scene, 4 output
// folder not writable, 5 some case failed (each is named on stderr), 130 interrupted. With
// `status`: 0 every case complete, 1 some still to run or running, 5 some failed.
int run_sweep(const SweepOptions& options);

}  // namespace weft
