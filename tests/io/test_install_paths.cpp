#include "io/install_paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;

TEST(InstallPaths, TheFirstFolderHoldingTheMarkerIsChosenAndEveryFolderTriedIsNamed) {
  testing::TempDir dir("weft_install_paths");
  fs::create_directories(dir.path() / "installed" / "shaders");
  fs::create_directories(dir.path() / "source" / "shaders");
  std::ofstream(dir.path() / "source" / "shaders" / "mesh.vert") << "#version 330 core\n";
  const std::string installed = (dir.path() / "installed" / "shaders").string();
  const std::string source = (dir.path() / "source" / "shaders").string();

  // An empty installed folder is passed over; the empty string (no program folder) is skipped.
  EXPECT_EQ(find_data_dir({"", installed, source}, "mesh.vert", "the shaders"), source);
  std::ofstream(dir.path() / "installed" / "shaders" / "mesh.vert") << "#version 330 core\n";
  EXPECT_EQ(find_data_dir({installed, source}, "mesh.vert", "the shaders"), installed);
  // "bin/../share" is written as the folder it names.
  EXPECT_EQ(
      find_data_dir({(dir.path() / "source" / ".." / "installed" / "shaders").string()}, "mesh.vert", "x"),
      installed);

  try {
    find_data_dir({installed, source}, "overlay.frag", "the viewer's shaders");
    FAIL() << "expected an IoError";
  } catch (const IoError& error) {
    EXPECT_EQ(std::string(error.what()),
              "cannot find the viewer's shaders (overlay.frag); looked in: " + installed + ", " + source);
  }
}

TEST(InstallPaths, TheProgramsFolderIsTheOneHoldingThisTest) {
  const std::string here = executable_dir();
  ASSERT_FALSE(here.empty());
  EXPECT_TRUE(fs::is_directory(here));
  EXPECT_TRUE(fs::exists(fs::path(here) / "weft_tests")) << here;
}

}  // namespace
}  // namespace weft
