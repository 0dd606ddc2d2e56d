#include "app/plot.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/gnuplot_quote.hpp"

extern char** environ;

namespace weft {

namespace {

namespace fs = std::filesystem;

struct Series {
  std::string title;
  std::string csv;
};

// One PNG: the same columns of one or more stats.csv files against the frame.
std::string plot_commands(const std::string& png, const std::string& title, const std::string& ylabel,
                          const std::vector<Series>& runs,
                          const std::vector<std::pair<std::string, std::string>>& columns,
                          bool skip_first_frame) {
  std::ostringstream s;
  s << "set terminal pngcairo size 1000,600 noenhanced\n"
    << "set output " << gnuplot_quote(png) << "\n"
    << "set datafile separator ','\n"
    << "set datafile columnheaders\n"
    << "set title " << gnuplot_quote(title) << "\n"
    << "set xlabel 'frame'\n"
    << "set ylabel " << gnuplot_quote(ylabel) << "\n"
    << "set grid\n"
    << "set key below horizontal\n"  // under the plot, so the curves keep the width
    << "plot ";
  bool first = true;
  for (const Series& run : runs) {
    for (const auto& [expression, label] : columns) {
      s << (first ? "" : ", \\\n     ") << gnuplot_quote(run.csv) << " using (column('frame')):(" << expression
        << ")" << (skip_first_frame ? " every ::1" : "") << " with lines title "
        << gnuplot_quote(runs.size() > 1 ? run.title + " " + label : label);
      first = false;
    }
  }
  s << "\nunset output\n";
  return s.str();
}

// Runs gnuplot on a script; returns an error message, empty on success.
std::string run_gnuplot(const std::string& script_path) {
  const char* argv[] = {"gnuplot", script_path.c_str(), nullptr};
  pid_t pid = -1;
  if (posix_spawnp(&pid, "gnuplot", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) {
    return "gnuplot not found: install it (apt-get install gnuplot-nox, or scripts/install-deps)";
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
      return "gnuplot not found: install it (apt-get install gnuplot-nox, or scripts/install-deps)";
    }
    return "gnuplot failed on " + script_path;
  }
  return {};
}

// Writes energy.png and time.png into `dir` for the given runs; each PNG appears whole.
std::string plot_into(const fs::path& dir, const std::vector<Series>& runs) {
  const std::string suffix = ".tmp." + std::to_string(::getpid());
  const std::vector<std::pair<std::string, std::string>> energy = {
      {"column('kinetic_energy')", "kinetic"},
      {"column('potential_energy')", "potential"},
      {"column('kinetic_energy') + column('potential_energy')", "total"},
      {"column('energy_dissipated')", "dissipated"},
      {"column('external_work')", "external work"},
      // The budget: flat at the initial energy when it closes (sim/energy_ledger.hpp).
      {"column('kinetic_energy') + column('potential_energy') + column('energy_dissipated') - "
       "column('external_work')",
       "total + dissipated - external work"}};
  const std::vector<std::pair<std::string, std::string>> energy_sweep = {
      {"column('kinetic_energy') + column('potential_energy')", "total"}};
  const std::vector<std::pair<std::string, std::string>> phases = {
      {"column('wall_ms')", "frame"},
      {"column('integrate_ms')", "integrate"},
      {"column('collisions_ms')", "collisions"},
      {"column('prepare_collisions_ms')", "prepare collisions"},
      {"column('record_ms')", "record"}};
  const std::vector<std::pair<std::string, std::string>> phases_sweep = {{"column('wall_ms')", "frame"}};
  const bool sweep = runs.size() > 1;
  const std::string energy_png = (dir / "energy.png").string(), time_png = (dir / "time.png").string();
  const std::string script =
      plot_commands(energy_png + suffix, "Energy per frame: " + dir.filename().string(), "energy (J)", runs,
                    sweep ? energy_sweep : energy, false) +
      plot_commands(time_png + suffix, "Wall time per frame: " + dir.filename().string(), "time (ms)", runs,
                    sweep ? phases_sweep : phases, true);
  const std::string script_path = (dir / ("plot.gp" + suffix)).string();
  write_file_atomically(script_path, [&](std::ostream& out) { out << script; });
  const std::string error = run_gnuplot(script_path);
  std::remove(script_path.c_str());
  for (const std::string& png : {energy_png, time_png}) {
    if (error.empty() && fs::exists(png + suffix)) {
      std::error_code ignored;
      fs::rename(png + suffix, png, ignored);
      if (ignored) return png + ": cannot rename into place: " + ignored.message();
    } else {
      std::remove((png + suffix).c_str());
    }
  }
  return error.empty() && !fs::exists(energy_png) ? "gnuplot wrote no " + energy_png : error;
}

// The columns plot_into reads.
const std::vector<std::string> plotted_columns = {
    "frame",        "kinetic_energy", "potential_energy",      "energy_dissipated", "wall_ms",
    "integrate_ms", "collisions_ms",  "prepare_collisions_ms", "record_ms",         "external_work"};

// Checks a stats.csv before gnuplot sees it (gnuplot says little about a damaged file): a header
// with the plotted columns, then rows of as many numbers. Returns "FILE: line N: ...", or empty.
std::string check_stats(const fs::path& csv) {
  std::ifstream in(csv);
  if (!in) return csv.string() + ": cannot open the file";
  std::string line;
  std::vector<std::string> header;
  if (std::getline(in, line)) {
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) header.push_back(field);
  }
  for (const std::string& column : plotted_columns) {
    if (std::find(header.begin(), header.end(), column) == header.end()) {
      return printable_text(csv.string() + ": line 1: expected the stats header of a weft run, with a \"" +
                            column + "\" column; got \"" + line.substr(0, 80) +
                            (line.size() > 80 ? "...\"" : "\""));
    }
  }
  int rows = 0;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::stringstream fields(line);
    size_t count = 0;
    std::string bad;
    for (std::string field; std::getline(fields, field, ','); ++count) {
      char* end = nullptr;
      std::strtod(field.c_str(), &end);
      if (bad.empty() && (field.empty() || *end != '\0'))
        bad = field.empty() ? "an empty field" : "\"" + field + "\"";
    }
    if (count != header.size() || !bad.empty()) {
      const std::string got = count != header.size() ? std::to_string(count) + " fields" : bad;
      return printable_text(csv.string() + ": line " + std::to_string(number) + ": expected " +
                            std::to_string(header.size()) +
                            " comma-separated numbers (one per header column), got " + got.substr(0, 80));
    }
    ++rows;
  }
  if (rows == 0) return csv.string() + ": line 2: expected at least one row of numbers after the header";
  return {};
}

}  // namespace

int run_plot(const PlotOptions& options) {
  const fs::path dir(options.dir);
  std::vector<fs::path> run_dirs;
  if (fs::exists(dir / "stats.csv")) {
    run_dirs.push_back(dir);
  } else if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_directory() && fs::exists(entry.path() / "stats.csv")) run_dirs.push_back(entry.path());
    }
    std::sort(run_dirs.begin(), run_dirs.end());
  }
  if (run_dirs.empty()) {
    std::fprintf(stderr, "weft plot: %s: expected a run folder with stats.csv, or a sweep folder of them\n",
                 options.dir.c_str());
    return 2;
  }
  for (const fs::path& run : run_dirs) {
    if (const std::string error = check_stats(run / "stats.csv"); !error.empty()) {
      std::fprintf(stderr, "weft plot: %s\n", error.c_str());
      return 2;
    }
  }
  try {
    std::vector<Series> all;
    for (const fs::path& run : run_dirs) {
      const Series series{run.filename().string(), (run / "stats.csv").string()};
      all.push_back(series);
      if (const std::string error = plot_into(run, {series}); !error.empty()) {
        std::fprintf(stderr, "weft plot: %s\n", error.c_str());
        return 4;
      }
      std::printf("%s\n%s\n", (run / "energy.png").c_str(), (run / "time.png").c_str());
    }
    if (run_dirs.size() > 1 || run_dirs.front() != dir) {
      if (const std::string error = plot_into(dir, all); !error.empty()) {
        std::fprintf(stderr, "weft plot: %s\n", error.c_str());
        return 4;
      }
      std::printf("%s\n%s\n", (dir / "energy.png").c_str(), (dir / "time.png").c_str());
    }
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft plot: %s\n", error.what());
    return 4;
  }
  return 0;
}

}  // namespace weft
