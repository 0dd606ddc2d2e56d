#include "ui/recording_player.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "core/error.hpp"
#include "io/recording.hpp"
#include "io/scene_file.hpp"
#include "temp_scene_file.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;

const char* const scene_text = R"({
  "fps": 30,
  "solver": {"integrator": "implicit_euler", "time_step": 0.005, "newton": {"tolerance": 1e-3}},
  "cloths": [{"name": "sheet", "grid": {"size": [1, 1], "resolution": [6, 6]},
              "transform": {"translation": [0, 0.56, 0], "rotation_degrees": [-90, 0, 0]},
              "springs": {"structural": {"stiffness": 200, "damping": 0.01}},
              "pins": {"corners": ["top_left"]}}],
  "colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5}]
})";

// A recording of `frames` frames written as the headless runner does (point caches, colliders.csv,
// recording.json, run.json with the scene), and each frame's positions as stepped.
struct RecordedScene {
  fs::path dir;
  std::vector<Positions> positions;  // per frame

  RecordedScene(const std::string& scene_path, int frames)
      : dir(fs::temp_directory_path() /
            ("weft_recording_player_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    SimulationSession session(scene_path, {});
    RecordingWriter writer(dir.string(), RecordingFormat::point_cache, frames, session.scene().fps);
    writer.start(session.world());
    for (int frame = 0; frame <= frames; ++frame) {
      if (frame > 0) session.advance_frame();
      writer.write_frame(frame, session.world());
      positions.push_back(session.world().cloths()[0].state.x);
    }
    nlohmann::json run;
    run["scene"] = scene_to_json(session.scene());
    std::ofstream(dir / "run.json") << run.dump(2);
  }
  ~RecordedScene() { fs::remove_all(dir); }
};

TEST(RecordingPlayer, ShowsTheRecordedPositionsOfAFrame) {
  const TempSceneFile file(scene_text);
  const RecordedScene recorded(file.path(), 8);
  Recording recording = read_recording(recorded.dir);
  ASSERT_EQ(recording.frames, 9);
  SimulationSession shown = SimulationSession::from_scene("run.json", recording.scene);
  RecordingPlayer player(std::move(recording), {});
  player.check_matches(shown);
  player.show(shown, 5);
  const Positions& x = shown.world().cloths()[0].state.x;
  // PC2 holds floats: equal to the stepped positions within float rounding.
  EXPECT_LT((x - recorded.positions[5]).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_GT((recorded.positions[5] - recorded.positions[4]).cwiseAbs().maxCoeff(), 1e-3) << "the cloth moves";
  EXPECT_DOUBLE_EQ(shown.world().time(), 5.0 / 30.0);
  const Positions expected_v = (recorded.positions[5] - recorded.positions[4]) * 30.0;
  EXPECT_LT((shown.world().cloths()[0].state.v - expected_v).cwiseAbs().maxCoeff(), 1e-4);
  player.show(shown, 99);
  EXPECT_EQ(player.frame(), 8) << "clamped to the last frame";
  EXPECT_LT((shown.world().cloths()[0].state.x - recorded.positions[8]).cwiseAbs().maxCoeff(), 1e-6);
  player.show(shown, 0);
  EXPECT_TRUE(shown.world().cloths()[0].state.v.isZero()) << "frame 0 has no earlier frame";
}

TEST(RecordingPlayer, PlaysAtTheRecordingsFrameRateAndStopsAtTheEnd) {
  const TempSceneFile file(scene_text);
  const RecordedScene recorded(file.path(), 4);
  RecordingPlayer player(read_recording(recorded.dir), {});
  EXPECT_FALSE(player.advance(1.0, 1.0)) << "not playing";
  player.playing = true;
  EXPECT_FALSE(player.advance(0.5 / 30.0, 1.0));
  EXPECT_TRUE(player.advance(0.6 / 30.0, 1.0));
  EXPECT_EQ(player.frame(), 1);
  EXPECT_TRUE(player.advance(1.0 / 30.0, 2.0));
  EXPECT_EQ(player.frame(), 3) << "twice the speed: two frames";
  EXPECT_TRUE(player.advance(10.0, 1.0));
  EXPECT_EQ(player.frame(), 4);
  EXPECT_FALSE(player.playing) << "stops at the last frame";
}

TEST(RecordingPlayer, RefusesASceneWhoseClothsAreNotTheRecordings) {
  const TempSceneFile file(scene_text);
  const RecordedScene recorded(file.path(), 1);
  Recording recording = read_recording(recorded.dir);
  const SimulationSession finer = SimulationSession::from_scene(
      "run.json", load_scene_file(file.path(), {"cloths.0.grid.resolution=[7,7]"}));
  RecordingPlayer player(std::move(recording), {});
  try {
    player.check_matches(finer);
    FAIL() << "a scene with other vertex counts was accepted";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("cloth \"sheet\": run.json's scene builds 49 vertices, the recording has 36"),
              std::string::npos)
        << error.what();
  }
}

TEST(RecordingPlayer, StatsTableErrorsNameTheFileAndLine) {
  const fs::path path = fs::temp_directory_path() / "weft_recording_player_stats.csv";
  std::ofstream(path) << "frame,time,contacts\n0,0,0\n1,0.03,x\n";
  try {
    read_stats_table(path);
    FAIL() << "a row with a word where a number goes was accepted";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find("weft_recording_player_stats.csv: line 3: expected 3 numbers"),
              std::string::npos)
        << error.what();
  }
  std::ofstream(path) << "frame,time,contacts\n0,0,0\n1,0.03,7\n";
  const StatsTable table = read_stats_table(path);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.column("contacts"), 2);
  EXPECT_EQ(table.column("none"), -1);
  EXPECT_EQ(table.rows[1][2], 7.0);
  fs::remove(path);
}

}  // namespace
}  // namespace weft
