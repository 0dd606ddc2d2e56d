#include "ui/simulation_session.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace weft {
namespace {

// A scene file in a fresh temporary folder, removed at the end of the test.
class SceneFile {
 public:
  explicit SceneFile(const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("weft_session_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json")) {
    write(text);
  }
  ~SceneFile() { std::filesystem::remove(path_); }
  void write(const std::string& text) const { std::ofstream(path_) << text; }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

const char* const small_scene = R"({
  "fps": 30,
  "solver": {"time_step": 0.005},
  "cloths": [{"grid": {"size": [1, 1], "resolution": [4, 4]}, "pins": {"corners": ["top_left"]}}]
})";

TEST(SimulationSession, StepsOnTheThreadsAskedForThroughResets) {
  const SceneFile file(small_scene);
  SimulationSession session(file.path(), {});
  EXPECT_EQ(session.threads(), 1);
  session.set_threads(3);
  EXPECT_EQ(session.world().settings.threads, 3);
  ASSERT_TRUE(session.reset());
  EXPECT_EQ(session.world().settings.threads, 3) << "a reset keeps the thread count";
  session.set_threads(0);
  EXPECT_EQ(session.threads(), std::max(1, omp_get_num_procs())) << "0: all cores";
}

TEST(SimulationSession, AdvancesOneFrameOfSimulatedTime) {
  const SceneFile file(small_scene);
  SimulationSession session(file.path(), {});
  EXPECT_EQ(session.schedule().steps_per_frame, 7);  // ceil((1/30) / 0.005)
  EXPECT_DOUBLE_EQ(session.world().settings.time_step, session.schedule().time_step);
  session.advance_frame();
  session.advance_frame();
  EXPECT_EQ(session.frame(), 2);
  EXPECT_NEAR(session.world().time(), 2.0 / 30.0, 1e-12);
}

TEST(SimulationSession, TimeStepSetsStepsPerFrame) {
  const SceneFile file(small_scene);
  SimulationSession session(file.path(), {});
  session.set_max_time_step(0.01);
  EXPECT_EQ(session.schedule().steps_per_frame, 4);
  EXPECT_NEAR(session.world().settings.time_step, 1.0 / 120.0, 1e-15);
}

TEST(SimulationSession, ResetReloadsAndAFailedResetKeepsTheWorld) {
  const SceneFile file(small_scene);
  SimulationSession session(file.path(), {"fps=60"});
  session.advance_frame();
  EXPECT_TRUE(session.reset());
  EXPECT_EQ(session.generation(), 1);
  EXPECT_EQ(session.world().time(), 0.0);
  EXPECT_EQ(session.scene().fps, 60.0);  // overrides still apply

  session.advance_frame();
  file.write(R"({"cloths": 3})");
  EXPECT_FALSE(session.reset());
  EXPECT_NE(session.error().find("/cloths"), std::string::npos) << session.error();
  EXPECT_EQ(session.generation(), 1);
  EXPECT_NEAR(session.world().time(), 1.0 / 60.0, 1e-12);
  EXPECT_EQ(session.world().cloths().size(), 1u);
}

TEST(SimulationSession, BadSceneThrows) {
  const SceneFile file(R"({"cloths": 3})");
  EXPECT_THROW(SimulationSession(file.path(), {}), SceneError);
}

}  // namespace
}  // namespace weft
