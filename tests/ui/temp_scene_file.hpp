#pragma once
// A scene file in the temporary folder, named after the running test, removed at the end.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace weft {

class TempSceneFile {
 public:
  explicit TempSceneFile(const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("weft_ui_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json")) {
    std::ofstream(path_) << text;
  }
  ~TempSceneFile() { std::filesystem::remove(path_); }
  TempSceneFile(const TempSceneFile&) = delete;
  TempSceneFile& operator=(const TempSceneFile&) = delete;
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace weft
