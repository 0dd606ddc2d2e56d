// Checkpoints: a world restored from one continues bit-identically; corrupt, cut-short, foreign
// and mismatched checkpoints are refused with the file and the reason.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

World small_world(const std::string& integrator, bool adaptive, int resolution = 6) {
  const auto document = nlohmann::json::parse(
      R"({
    "solver": {"time_step": 0.002, "integrator": ")" +
      integrator + R"(", "adaptive": {"enabled": )" + (adaptive ? "true" : "false") + R"(}},
    "cloths": [{"name": "sheet", "grid": {"size": [1, 1], "resolution": [)" +
      std::to_string(resolution) + "," + std::to_string(resolution) + R"(]},
                "transform": {"translation": [0, 0.7, 0], "rotation_degrees": [-90, 0, 0]},
                "pins": {"corners": ["top_left"]}}],
    "colliders": [{"type": "sphere", "name": "ball", "radius": 0.3}]
  })");
  return build_world(parse_scene(document, "<inline>"));
}

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const IoError& error) {
    return error.what();
  }
  return "";
}

class CheckpointRoundTrip : public ::testing::TestWithParam<std::pair<std::string, bool>> {};

TEST_P(CheckpointRoundTrip, RestoredWorldContinuesBitIdentically) {
  const auto [integrator, adaptive] = GetParam();
  TempDir dir("weft_checkpoint");
  World original = small_world(integrator, adaptive);
  for (int step = 0; step < 40; ++step) original.step();
  write_checkpoint(dir.file("checkpoint.bin"), capture_checkpoint(original, 7, "{\"name\": \"x\"}", 1.25));

  const Checkpoint read = read_checkpoint(dir.file("checkpoint.bin"));
  EXPECT_EQ(read.frame, 7);
  EXPECT_EQ(read.scene_json, "{\"name\": \"x\"}");
  EXPECT_EQ(read.initial_energy, 1.25);
  EXPECT_EQ(read.time, original.time());
  World resumed = small_world(integrator, adaptive);
  restore_checkpoint(read, resumed, "checkpoint.bin");
  EXPECT_EQ(resumed.time(), original.time());

  for (int step = 0; step < 40; ++step) {
    original.step();
    resumed.step();
  }
  EXPECT_EQ(resumed.time(), original.time());
  // Bit-identical, not merely close.
  EXPECT_TRUE(resumed.cloths()[0].state.x == original.cloths()[0].state.x);
  EXPECT_TRUE(resumed.cloths()[0].state.v == original.cloths()[0].state.v);
  EXPECT_EQ(resumed.adaptive_state(0).accepted, original.adaptive_state(0).accepted);
}

INSTANTIATE_TEST_SUITE_P(Integrators, CheckpointRoundTrip,
                         ::testing::Values(std::make_pair(std::string("symplectic_euler"), false),
                                           std::make_pair(std::string("midpoint"), true),
                                           std::make_pair(std::string("implicit_euler"), false)));

TEST(Checkpoint, KeepsRestPositionsAndColliders) {
  TempDir dir("weft_checkpoint_rest");
  World world = small_world("symplectic_euler", false);
  world.cloths()[0].model.rest_positions(1, 3) += 0.01;  // as plasticity would
  world.colliders()[0].center = Vec3(0.1, 0.2, 0.3);
  write_checkpoint(dir.file("c.bin"), capture_checkpoint(world, 1, "{}", 0.0));
  World fresh = small_world("symplectic_euler", false);
  restore_checkpoint(read_checkpoint(dir.file("c.bin")), fresh, "c.bin");
  EXPECT_TRUE(fresh.cloths()[0].model.rest_positions == world.cloths()[0].model.rest_positions);
  EXPECT_EQ(fresh.colliders()[0].center, Vec3(0.1, 0.2, 0.3));
}

TEST(Checkpoint, CorruptOrForeignFilesAreRefused) {
  TempDir dir("weft_checkpoint_bad");
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint(path, capture_checkpoint(small_world("symplectic_euler", false), 3, "{}", 0.0));
  const auto size = fs::file_size(path);

  // One flipped byte in the middle of the state.
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(size / 2));
    file.put('\x55');
  }
  EXPECT_NE(error_of([&] { read_checkpoint(path); }).find("checkpoint.bin: checkpoint checksum: mismatch"),
            std::string::npos);

  // Cut short, as by a full disk.
  write_checkpoint(path, capture_checkpoint(small_world("symplectic_euler", false), 3, "{}", 0.0));
  fs::resize_file(path, size - 100);
  EXPECT_NE(error_of([&] { read_checkpoint(path); }).find("checkpoint size"), std::string::npos);

  // Another version.
  write_checkpoint(path, capture_checkpoint(small_world("symplectic_euler", false), 3, "{}", 0.0));
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(8);
    file.put('\x09');
  }
  EXPECT_NE(error_of([&] { read_checkpoint(path); }).find("checkpoint version: expected 1, got 9"),
            std::string::npos);

  std::ofstream(dir.file("text.bin")) << "hello, not a checkpoint at all";
  EXPECT_NE(error_of([&] { read_checkpoint(dir.file("text.bin")); }).find("not a Weft checkpoint"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_checkpoint(dir.file("none.bin")); }).find("none.bin: cannot open"),
            std::string::npos);
}

TEST(Checkpoint, RestoringIntoADifferentWorldIsRefused) {
  const Checkpoint checkpoint = capture_checkpoint(small_world("symplectic_euler", false, 6), 3, "{}", 0.0);
  World other = small_world("symplectic_euler", false, 7);
  const std::string message = error_of([&] { restore_checkpoint(checkpoint, other, "ck.bin"); });
  EXPECT_NE(message.find("ck.bin: checkpoint cloth 0 (\"sheet\", 36 vertices) does not match"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace weft
