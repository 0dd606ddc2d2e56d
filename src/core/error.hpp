#pragma once
// Error types for bad input. Their messages name the file, the place in it and what was expected.
#include <stdexcept>
#include <string>

namespace weft {

// A file could not be read or written (missing, malformed, unwritable).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A scene description is invalid: `file` and the JSON pointer `json_path` locate the problem.
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, const std::string& json_path, const std::string& message)
      : std::runtime_error(file + ": " + (json_path.empty() ? std::string("/") : json_path) + ": " + message),
        file_(file),
        json_path_(json_path) {}
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }

 private:
  std::string file_;
  std::string json_path_;
};

}  // namespace weft
