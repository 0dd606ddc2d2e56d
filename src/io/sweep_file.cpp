#include "io/sweep_file.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "io/recording.hpp"
#include "sim/world.hpp"

namespace weft {

namespace fs = std::filesystem;
using ordered_json = nlohmann::ordered_json;

namespace {

const std::set<std::string> sweep_keys = {
    "name",   "scene", "out",  "frames", "threads", "jobs", "checkpoint_every",
    "format", "set",   "grid", "slurm"};
const std::set<std::string> slurm_keys = {"partition", "time", "memory", "max_parallel", "sbatch"};

std::string known_list(const std::set<std::string>& keys) {
  std::string list;
  for (const std::string& key : keys) list += (list.empty() ? "" : ", ") + key;
  return list;
}

void check_keys(const ordered_json& object, const std::set<std::string>& known, const std::string& path,
                const std::string& file) {
  for (const auto& item : object.items()) {
    if (!known.count(item.key())) {
      throw SceneError(file, path + "/" + item.key(),
                       "unknown key \"" + item.key() + "\" (known here: " + known_list(known) + ")");
    }
  }
}

std::string read_string(const ordered_json& object, const std::string& key, const std::string& path,
                        const std::string& file, const std::string& fallback) {
  if (!object.contains(key)) return fallback;
  const ordered_json& value = object[key];
  if (!value.is_string() || value.get<std::string>().empty()) {
    throw SceneError(file, path + "/" + key, "expected a non-empty string, got " + value.dump());
  }
  return value.get<std::string>();
}

int read_int(const ordered_json& object, const std::string& key, const std::string& path,
             const std::string& file, int fallback, int minimum, int maximum = 1000000000) {
  if (!object.contains(key)) return fallback;
  const ordered_json& value = object[key];
  if (!value.is_number_integer() || value.get<long long>() < minimum || value.get<long long>() > maximum) {
    throw SceneError(file, path + "/" + key,
                     "expected an integer >= " + std::to_string(minimum) +
                         (maximum < 1000000000 ? " and <= " + std::to_string(maximum) : std::string()) +
                         ", got " + value.dump());
  }
  return value.get<int>();
}

std::vector<std::string> read_strings(const ordered_json& object, const std::string& key,
                                      const std::string& path, const std::string& file) {
  std::vector<std::string> strings;
  if (!object.contains(key)) return strings;
  const ordered_json& value = object[key];
  if (!value.is_array())
    throw SceneError(file, path + "/" + key, "expected an array of strings, got " + value.dump());
  for (size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_string()) {
      throw SceneError(file, path + "/" + key + "/" + std::to_string(i),
                       "expected a string, got " + value[i].dump());
    }
    strings.push_back(value[i].get<std::string>());
  }
  return strings;
}

// A value as it goes into a case name: letters, digits, '.', '+', '-'; anything else as '_'.
std::string name_part(const std::string& text) {
  std::string part;
  for (const char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '+' || c == '-';
    if (keep) {
      part += c;
    } else if (!part.empty() && part.back() != '_') {
      part += '_';
    }
  }
  while (!part.empty() && part.back() == '_') part.pop_back();
  return part.empty() ? "x" : part;
}

std::vector<std::string> path_segments(const std::string& path) {
  std::vector<std::string> segments;
  std::string current;
  for (const char c : path) {
    if (c == '.' || c == '/') {
      if (!current.empty()) segments.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) segments.push_back(current);
  return segments;
}

// The shortest tail of each grid path that no other path shares ("stiffness", but
// "structural.stiffness" when "shear.stiffness" is swept too).
std::vector<std::string> short_labels(const std::vector<std::string>& paths) {
  std::vector<std::vector<std::string>> segments;
  for (const std::string& path : paths) segments.push_back(path_segments(path));
  const auto tail = [&](size_t k, size_t depth) {
    const std::vector<std::string>& parts = segments[k];
    std::string label;
    for (size_t s = parts.size() > depth ? parts.size() - depth : 0; s < parts.size(); ++s) {
      label += (label.empty() ? "" : ".") + parts[s];
    }
    return label;
  };
  std::vector<std::string> labels(paths.size());
  for (size_t k = 0; k < paths.size(); ++k) {
    for (size_t depth = 1;; ++depth) {
      labels[k] = tail(k, depth);
      bool unique = true;
      for (size_t j = 0; j < paths.size() && unique; ++j) unique = j == k || tail(j, depth) != labels[k];
      if (unique || depth >= segments[k].size()) break;
    }
  }
  return labels;
}

}  // namespace

SweepDesc load_sweep_file(const std::string& path) {
  // A folder opens as a stream but fails on the first read (an uncaught ios_base::failure).
  std::error_code ignored;
  if (fs::is_directory(path, ignored)) {
    throw SceneError(path, "", "is a folder; expected a sweep file (JSON), e.g. sweeps/drape_stiffness.json");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, "", "cannot open the sweep file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path, "", "cannot read the sweep file");
  return parse_sweep(text.str(), path);
}

SweepDesc parse_sweep(const std::string& text, const std::string& path) {
  const ordered_json document = ordered_json::parse(text, nullptr, false);
  if (document.is_discarded()) throw SceneError(path, "", "invalid JSON");
  if (!document.is_object()) throw SceneError(path, "", "expected an object");
  check_keys(document, sweep_keys, "", path);

  SweepDesc sweep;
  sweep.source_file = path;
  sweep.name = name_part(read_string(document, "name", "", path, fs::path(path).stem().string()));
  if (!document.contains("scene"))
    throw SceneError(path, "/scene", "missing: expected the scene file to sweep");
  const fs::path scene = read_string(document, "scene", "", path, "");
  sweep.scene = scene.is_absolute() ? scene.string()
                                    : (fs::path(path).parent_path() / scene).lexically_normal().string();
  sweep.out = read_string(document, "out", "", path, (fs::path("out") / sweep.name).string());
  sweep.frames = read_int(document, "frames", "", path, -1, 0);
  sweep.threads = read_int(document, "threads", "", path, 1, 1, max_threads);
  sweep.jobs = read_int(document, "jobs", "", path, 0, 0, max_sweep_jobs);
  sweep.checkpoint_every =
      read_int(document, "checkpoint_every", "", path, default_sweep_checkpoint_every, 0);
  sweep.format = read_string(document, "format", "", path, "pc2");
  RecordingFormat format;
  if (!recording_format_from_string(sweep.format, format)) {
    throw SceneError(path, "/format", "expected \"pc2\", \"obj\" or \"both\", got \"" + sweep.format + "\"");
  }
  sweep.overrides = read_strings(document, "set", "", path);
  for (size_t i = 0; i < sweep.overrides.size(); ++i) {
    if (sweep.overrides[i].find('=') == std::string::npos) {
      throw SceneError(path, "/set/" + std::to_string(i),
                       "expected \"path=value\", got \"" + sweep.overrides[i] + "\"");
    }
  }

  if (!document.contains("grid"))
    throw SceneError(path, "/grid", "missing: expected an object of path: [values]");
  const ordered_json& grid = document["grid"];
  if (!grid.is_object() || grid.empty()) {
    throw SceneError(path, "/grid", "expected a non-empty object of path: [values], got " + grid.dump());
  }
  long long cases = 1;
  for (const auto& item : grid.items()) {
    const ordered_json& values = item.value();
    if (!values.is_array() || values.empty()) {
      throw SceneError(path, "/grid/" + item.key(),
                       "expected a non-empty array of values, got " + values.dump());
    }
    // Checked key by key, so that the product cannot overflow either.
    cases *= static_cast<long long>(values.size());
    if (cases > max_sweep_cases) {
      throw SceneError(path, "/grid/" + item.key(),
                       "the grid has more than " + std::to_string(max_sweep_cases) +
                           " combinations up to this key; expected at most that many cases in one sweep "
                           "(split it into several sweep files)");
    }
    std::vector<nlohmann::json> list;
    for (const ordered_json& value : values) list.push_back(nlohmann::json::parse(value.dump()));
    sweep.grid.emplace_back(item.key(), list);
  }

  if (document.contains("slurm")) {
    const ordered_json& slurm = document["slurm"];
    if (!slurm.is_object()) throw SceneError(path, "/slurm", "expected an object, got " + slurm.dump());
    check_keys(slurm, slurm_keys, "/slurm", path);
    sweep.slurm.partition = read_string(slurm, "partition", "/slurm", path, "");
    sweep.slurm.time = read_string(slurm, "time", "/slurm", path, sweep.slurm.time);
    sweep.slurm.memory = read_string(slurm, "memory", "/slurm", path, sweep.slurm.memory);
    sweep.slurm.max_parallel = read_int(slurm, "max_parallel", "/slurm", path, 0, 0);
    sweep.slurm.sbatch = read_strings(slurm, "sbatch", "/slurm", path);
    for (size_t i = 0; i < sweep.slurm.sbatch.size(); ++i) {
      if (sweep.slurm.sbatch[i].rfind("--", 0) != 0 ||
          sweep.slurm.sbatch[i].find('\n') != std::string::npos) {
        throw SceneError(
            path, "/slurm/sbatch/" + std::to_string(i),
            "expected an sbatch option such as \"--account=NAME\", got \"" + sweep.slurm.sbatch[i] + "\"");
      }
    }
  }
  return sweep;
}

std::vector<SweepCase> expand_sweep(const SweepDesc& sweep) {
  std::vector<std::string> paths;
  size_t total = 1;
  for (const auto& [path, values] : sweep.grid) {
    paths.push_back(path);
    total *= values.size();
  }
  const std::vector<std::string> labels = short_labels(paths);
  const int digits = std::max(3, static_cast<int>(std::to_string(total - 1).size()));

  std::vector<SweepCase> cases;
  for (size_t index = 0; index < total; ++index) {
    SweepCase sweep_case;
    sweep_case.overrides = sweep.overrides;
    std::string number = std::to_string(index);
    sweep_case.name = std::string(digits - number.size(), '0') + number;
    // Mixed-radix digits of the index, the last grid key varying fastest.
    size_t rest = index, stride = total;
    for (size_t k = 0; k < sweep.grid.size(); ++k) {
      const std::vector<nlohmann::json>& values = sweep.grid[k].second;
      stride /= values.size();
      const nlohmann::json& value = values[rest / stride];
      rest %= stride;
      const std::string text = value.is_string() ? value.get<std::string>() : value.dump();
      sweep_case.overrides.push_back(sweep.grid[k].first + "=" + value.dump());
      sweep_case.name += "_" + name_part(labels[k]) + "-" + name_part(text);
    }
    cases.push_back(std::move(sweep_case));
  }
  return cases;
}

}  // namespace weft
