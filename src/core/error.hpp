#pragma once
// Error types for bad input. Their messages name the file, the place in it and what was expected.
#include <stdexcept>
#include <string>

namespace weft {

// `text` with control bytes and bytes that are not UTF-8 written as \xNN, so a message quoting a
// binary file cannot send raw bytes to the terminal. Valid UTF-8 (a file name with accents) stays.
std::string printable_text(const std::string& text);

// A file could not be read or written (missing, malformed, unwritable).
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& message) : std::runtime_error(printable_text(message)) {}
};

// A scene description is invalid: `file` and the JSON pointer `json_path` locate the problem.
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& file, const std::string& json_path, const std::string& message)
      : std::runtime_error(printable_text(file + ": " + (json_path.empty() ? std::string("/") : json_path) +
                                          ": " + message)),
        file_(file),
        json_path_(json_path) {}
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }

 private:
  std::string file_;
  std::string json_path_;
};

}  // namespace weft
