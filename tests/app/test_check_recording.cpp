// `weft check DIR` on headless recordings: exit 0 when every frame is clean, 1 (a line per
// tangled frame) when one is not, 2 with the file named on a missing folder or a truncated cache.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;

// A short recording of `scene` into `out`.
void record(const std::string& scene, const fs::path& out, const TempDir& dir,
            const std::vector<std::string>& more) {
  std::vector<std::string> command = {weft_program, "--headless", scene, "--quiet", "--out", out.string()};
  command.insert(command.end(), more.begin(), more.end());
  const ProgramResult result = run_program(command, dir.file("record.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
}

ProgramResult check(const fs::path& out, const TempDir& dir) {
  return run_program({weft_program, "check", out.string()}, dir.file("check.txt"));
}

TEST(CheckRecording, ACleanRecordingExitsZero) {
  TempDir dir("weft_check_clean");
  const fs::path out = dir.path() / "out";
  record(source_dir + "/scenes/drape_sphere.json", out, dir,
         {"--frames", "3", "--set", "cloths.0.grid.resolution=[16,16]"});
  const ProgramResult result = check(out, dir);
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "4 frames checked, all clean")) << result.error_text;
}

TEST(CheckRecording, ATangledRecordingExitsOneAndSaysEachFrame) {
  TempDir dir("weft_check_tangled");
  for (const char* format : {"pc2", "obj"}) {
    const fs::path out = dir.path() / format;
    // Untangling off, so that the sheets stay crossed in every frame.
    record(source_dir + "/tests/data/tangled_sheets.json", out, dir,
           {"--format", format, "--set", "collision.untangle=false"});
    const ProgramResult result = check(out, dir);
    EXPECT_EQ(result.exit_code, 1) << format << ": " << result.error_text;
    EXPECT_TRUE(contains(result.error_text, "frame 0 (t = 0 s): tangled: cloths \"flat\" and \"tilted\": "))
        << format << ": " << result.error_text;
    EXPECT_TRUE(contains(result.error_text, "3 frames checked, 3 tangled (first: frame 0;"))
        << format << ": " << result.error_text;
  }
}

TEST(CheckRecording, AMissingFolderOrATruncatedCacheExitsTwoNamingTheFile) {
  TempDir dir("weft_check_bad");
  const ProgramResult missing = check(dir.path() / "nowhere", dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.error_text, (dir.path() / "nowhere").string() + ": no such folder"))
      << missing.error_text;

  const fs::path out = dir.path() / "out";
  record(source_dir + "/scenes/drape_sphere.json", out, dir,
         {"--frames", "3", "--set", "cloths.0.grid.resolution=[16,16]"});
  // Cut the cache in the middle of its last sample.
  const fs::path cache = out / "cloth.pc2";
  fs::resize_file(cache, fs::file_size(cache) - 100);
  const ProgramResult truncated = check(out, dir);
  EXPECT_EQ(truncated.exit_code, 2) << truncated.error_text;
  EXPECT_TRUE(contains(truncated.error_text, cache.string() + ": ")) << truncated.error_text;
}

}  // namespace
}  // namespace weft
