#pragma once
// `weft plot DIR`: PNG plots of a run's stats.csv with gnuplot: energy.png (kinetic, potential,
// total and dissipated energy per frame, external work, and the budget total + dissipated -
// external work, flat when it closes) and time.png (milliseconds per phase per frame). For a
// sweep folder (cases in sub-folders) each case gets its plots and the folder gets both plots
// with one line per case.
#include <string>

namespace weft {

struct PlotOptions {
  std::string dir;
};

// Exit codes: 0 plots written, 2 no stats.csv in DIR or its sub-folders, 4 gnuplot missing or
// failed (the message says which).
int run_plot(const PlotOptions& options);

}  // namespace weft
