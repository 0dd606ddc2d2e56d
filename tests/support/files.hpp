#pragma once
// Small file helpers for tests that check what the weft program wrote.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace weft::testing {

inline std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

inline nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in, nullptr, false);
}

inline int count_lines(const std::filesystem::path& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

// True if any file under `dir` is a leftover temporary of an atomic write ("NAME.tmp.PID").
inline bool has_temporary_files(const std::filesystem::path& dir) {
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (entry.path().filename().string().find(".tmp.") != std::string::npos) return true;
  }
  return false;
}

// One stats.csv column, a value per frame.
inline std::vector<double> stats_column(const std::filesystem::path& stats, const std::string& name) {
  std::ifstream in(stats);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream fields(line);
  for (std::string field; std::getline(fields, field, ',');) header.push_back(field);
  const auto column = std::find(header.begin(), header.end(), name) - header.begin();
  EXPECT_LT(column, static_cast<long>(header.size())) << stats << " has no column " << name;
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    for (long i = 0; i <= column && std::getline(row, field, ','); ++i) {
    }
    values.push_back(std::stod(field));
  }
  return values;
}

}  // namespace weft::testing
