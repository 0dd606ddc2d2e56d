#include "ui/simulation_worker.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>
#include <vector>

#include "temp_scene_file.hpp"

namespace weft {
namespace {

// A pinned cloth falling onto a sphere: contacts within a few dozen steps.
const char* const scene = R"({
  "fps": 30,
  "solver": {"integrator": "implicit_euler", "time_step": 0.005, "newton": {"tolerance": 1e-3}},
  "cloths": [{"grid": {"size": [1, 1], "resolution": [8, 8]},
              "transform": {"translation": [0, 0.56, 0], "rotation_degrees": [-90, 0, 0]},
              "springs": {"structural": {"stiffness": 200, "damping": 0.01}},
              "pins": {"corners": ["top_left"]}}],
  "colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5}]
})";

// The worker's session after `steps` steps and the same session stepped here, compared bit for bit.
void expect_same_state(const SimulationSession& shown, const SimulationSession& reference) {
  ASSERT_EQ(shown.world().cloths().size(), reference.world().cloths().size());
  for (size_t c = 0; c < shown.world().cloths().size(); ++c) {
    EXPECT_TRUE(shown.world().cloths()[c].state.x == reference.world().cloths()[c].state.x) << "cloth " << c;
    EXPECT_TRUE(shown.world().cloths()[c].state.v == reference.world().cloths()[c].state.v) << "cloth " << c;
  }
  EXPECT_EQ(shown.world().time(), reference.world().time());
  EXPECT_EQ(shown.frame(), reference.frame());
  EXPECT_EQ(shown.step_in_frame(), reference.step_in_frame());
  EXPECT_EQ(shown.world().contacts().size(), reference.world().contacts().size());
}

void step_on_worker(SimulationWorker& worker, int steps) {
  for (int i = 0; i < steps; ++i) worker.submit([](SimulationSession& session) { session.advance_step(); });
  worker.wait_for_commands();
  EXPECT_TRUE(worker.exchange(VertexDrag(), 1.0));
}

TEST(SimulationWorker, ShowsTheLastFinishedStepBitForBit) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  SimulationSession reference(file.path(), {});
  step_on_worker(worker, 40);
  for (int i = 0; i < 40; ++i) reference.advance_step();
  ASSERT_GT(reference.world().contacts().size(), 0u) << "the scene should touch the sphere by now";
  expect_same_state(worker.shown(), reference);
}

TEST(SimulationWorker, TheUiNeverWaitsForAStepUnderWay) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  step_on_worker(worker, 2);
  const double shown_time = worker.shown().world().time();
  // A step the test holds: it starts, then waits for the gate.
  std::promise<void> entered, gate;
  std::shared_future<void> gate_open = gate.get_future().share();
  worker.submit([&entered, gate_open](SimulationSession& session) {
    entered.set_value();
    gate_open.wait();
    session.advance_step();
  });
  entered.get_future().wait();
  // While it is held the UI's calls return (a wait would never end: the gate opens after them).
  auto ui = std::async(std::launch::async, [&worker] {
    bool changed = false;
    for (int frame = 0; frame < 100; ++frame) changed |= worker.exchange(VertexDrag(), 1.0);
    worker.submit([](SimulationSession& session) { session.advance_step(); });
    return changed;
  });
  const bool returned = ui.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
  gate.set_value();
  ASSERT_TRUE(returned) << "exchange() or submit() waited for the step under way";
  EXPECT_FALSE(ui.get()) << "nothing new was published while the step was held";
  EXPECT_EQ(worker.shown().world().time(), shown_time);
  worker.wait_for_commands();
  worker.exchange(VertexDrag(), 1.0);
  EXPECT_EQ(
      worker.shown().frame() * worker.shown().schedule().steps_per_frame + worker.shown().step_in_frame(), 4);
}

// Edits made on the drawn mirror reach the worker's session with the next exchange(), before its
// next step, and not before.
TEST(SimulationWorker, EditsTakeEffectAtTheNextStepAfterTheyAreSent) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  SimulationSession reference(file.path(), {});
  step_on_worker(worker, 3);
  for (int i = 0; i < 3; ++i) reference.advance_step();

  const auto edit = [](SimulationSession& session) {
    session.world().settings.gravity = Vec3(0.0, -4.0, 1.0);
    ClothMaterial material = read_material(session.world().cloths()[0].model);
    material.area_density *= 3.0;
    material.mass_damping = 0.7;
    apply_material(session.world().cloths()[0].model, material);
    session.world().contact_material(0).kinetic_friction = 0.05;
  };
  edit(worker.shown());
  // Not sent yet: the worker's next step is the unedited one.
  worker.submit([](SimulationSession& session) { session.advance_step(); });
  worker.wait_for_commands();
  reference.advance_step();
  // exchange() sends the edit and takes in the unedited step; the edit survives it on the mirror.
  EXPECT_TRUE(worker.exchange(VertexDrag(), 1.0));
  expect_same_state(worker.shown(), reference);
  EXPECT_EQ(worker.shown().world().settings.gravity, Vec3(0.0, -4.0, 1.0));

  edit(reference);
  step_on_worker(worker, 5);
  for (int i = 0; i < 5; ++i) reference.advance_step();
  expect_same_state(worker.shown(), reference);
  EXPECT_EQ(worker.shown().world().cloths()[0].model.mass, reference.world().cloths()[0].model.mass);
}

TEST(SimulationWorker, PlayingNeverShowsATornState) {
  const TempSceneFile file(scene);
  // Positions after every step of the same session stepped here.
  SimulationSession reference(file.path(), {});
  std::vector<Positions> after_step{reference.world().cloths()[0].state.x};
  for (int i = 0; i < 600; ++i) {
    reference.advance_step();
    after_step.push_back(reference.world().cloths()[0].state.x);
  }
  SimulationWorker worker(SimulationSession(file.path(), {}));
  worker.shown().playing = true;
  worker.submit([](SimulationSession& session) { session.playing = true; });
  const int steps_per_frame = worker.shown().schedule().steps_per_frame;
  const double h = worker.shown().schedule().time_step;
  int states_seen = 0, last_index = 0;
  const auto start = std::chrono::steady_clock::now();
  while (last_index < 150 && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    // Settings go out on every exchange; applied again and again they must change nothing.
    if (!worker.exchange(VertexDrag(), 8.0)) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    const SimulationSession& shown = worker.shown();
    const int index = shown.frame() * steps_per_frame + shown.step_in_frame();
    ASSERT_LT(index, static_cast<int>(after_step.size()));
    EXPECT_NEAR(shown.world().time(), index * h, 1e-9) << "time and step count from one step";
    ASSERT_TRUE(shown.world().cloths()[0].state.x == after_step[static_cast<size_t>(index)])
        << "the positions drawn are not those of step " << index;
    EXPECT_GE(index, last_index);
    last_index = index;
    ++states_seen;
  }
  worker.shown().playing = false;
  worker.submit([](SimulationSession& session) { session.playing = false; });
  EXPECT_GE(last_index, 150) << "played too slowly";
  EXPECT_GE(states_seen, 2);
}

TEST(SimulationWorker, AResetBringsANewMirrorAndDropsTheOldWorldsEdits) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  step_on_worker(worker, 3);
  const int generation = worker.shown().generation();
  worker.shown().world().settings.gravity = Vec3::Zero();  // an edit of the world about to go
  worker.submit([](SimulationSession& session) { session.reset(); });
  worker.wait_for_commands();
  EXPECT_TRUE(worker.exchange(VertexDrag(), 1.0));
  EXPECT_EQ(worker.shown().generation(), generation + 1);
  EXPECT_EQ(worker.shown().frame(), 0);
  EXPECT_EQ(worker.shown().world().time(), 0.0);
  EXPECT_EQ(worker.shown().world().settings.gravity, Vec3(0.0, -9.81, 0.0)) << "the file's gravity";
  SimulationSession reference(file.path(), {});
  step_on_worker(worker, 4);
  for (int i = 0; i < 4; ++i) reference.advance_step();
  expect_same_state(worker.shown(), reference);
}

TEST(SimulationWorker, DragsTheVertexTheUiHolds) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  SimulationSession reference(file.path(), {});
  VertexDrag drag;
  drag.begin(0, 40, Vec3(0.3, 1.2, 0.1));
  reference.before_step = [&drag](World& world) { drag.apply(world); };
  worker.exchange(drag, 1.0);
  step_on_worker(worker, 1);  // its exchange lets go
  reference.advance_step();
  drag.end(reference.world());
  step_on_worker(worker, 2);
  reference.advance_step();
  reference.advance_step();
  expect_same_state(worker.shown(), reference);
  SimulationSession undragged(file.path(), {});
  for (int i = 0; i < 3; ++i) undragged.advance_step();
  EXPECT_FALSE(worker.shown().world().cloths()[0].state.x == undragged.world().cloths()[0].state.x);
}

void frames_on_worker(SimulationWorker& worker, int frames) {
  for (int i = 0; i < frames; ++i) worker.submit([](SimulationSession& session) { session.advance_frame(); });
  worker.wait_for_commands();
  worker.exchange(VertexDrag(), 1.0);
}

TEST(SimulationWorker, KeepsEachFramesStartWithinItsMemoryBound) {
  const TempSceneFile file(scene);
  SimulationSession reference(file.path(), {});
  std::vector<Positions> at_frame{reference.world().cloths()[0].state.x};
  for (int frame = 1; frame <= 10; ++frame) {
    reference.advance_frame();
    at_frame.push_back(reference.world().cloths()[0].state.x);
  }
  SimulationWorker worker(SimulationSession(file.path(), {}));
  frames_on_worker(worker, 10);
  const HistoryRange range = worker.history();
  EXPECT_EQ(range.first, 0);
  EXPECT_EQ(range.last, 10) << "the latest frame is kept too";
  for (const int frame : {0, 4, 10}) {
    const std::shared_ptr<const Checkpoint> state = worker.history_frame(frame);
    ASSERT_NE(state, nullptr);
    EXPECT_EQ(state->frame, frame);
    EXPECT_TRUE(state->cloths[0].x == at_frame[static_cast<size_t>(frame)]) << "frame " << frame;
  }
  EXPECT_EQ(worker.history_frame(11), nullptr);

  // Bounded: room for three frames keeps the latest three.
  SimulationWorker bounded(SimulationSession(file.path(), {}), 3 * range.bytes / 11 + range.bytes / 22);
  frames_on_worker(bounded, 10);
  EXPECT_EQ(bounded.history().first, 8);
  EXPECT_EQ(bounded.history().last, 10);
  EXPECT_LE(bounded.history().bytes, bounded.history_limit());
  SimulationWorker none(SimulationSession(file.path(), {}), 0);
  frames_on_worker(none, 3);
  EXPECT_TRUE(none.history().empty());
}

TEST(SimulationWorker, AResetKeepsOnlyTheNewWorldsFramesEvenWhenStepsFollowInTheSameBatch) {
  const TempSceneFile file(scene);
  SimulationSession reference(file.path(), {});
  reference.advance_frame();
  const Positions frame_one = reference.world().cloths()[0].state.x;
  SimulationWorker worker(SimulationSession(file.path(), {}));
  frames_on_worker(worker, 5);
  worker.shown().world().settings.gravity = Vec3::Zero();  // the old world's edit
  worker.exchange(VertexDrag(), 1.0);
  worker.submit([](SimulationSession& session) { session.reset(); });
  worker.submit([](SimulationSession& session) { session.advance_frame(); });
  worker.submit([](SimulationSession& session) { session.advance_frame(); });
  worker.wait_for_commands();
  worker.exchange(VertexDrag(), 1.0);
  const HistoryRange range = worker.history();
  EXPECT_EQ(range.first, 0);
  EXPECT_EQ(range.last, 2);
  const std::shared_ptr<const Checkpoint> one = worker.history_frame(1);
  ASSERT_NE(one, nullptr);
  EXPECT_TRUE(one->cloths[0].x == frame_one) << "frame 1 of the new world, under the file's gravity";
}

TEST(SimulationWorker, ResumesFromAFrameOfItsHistoryAsAnUninterruptedRun) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  frames_on_worker(worker, 8);
  const int generation = worker.shown().generation();
  worker.resume_from(3);
  worker.wait_for_commands();
  worker.exchange(VertexDrag(), 1.0);
  EXPECT_EQ(worker.shown().frame(), 3);
  EXPECT_EQ(worker.shown().generation(), generation) << "the same world's meshes";
  EXPECT_EQ(worker.history().last, 3) << "the frames after it are gone";
  frames_on_worker(worker, 4);
  SimulationSession reference(file.path(), {});
  for (int i = 0; i < 7; ++i) reference.advance_frame();
  expect_same_state(worker.shown(), reference);
}

TEST(SimulationWorker, AResumeKeepsTheSettingsEditedSince) {
  const TempSceneFile file(scene);
  SimulationWorker worker(SimulationSession(file.path(), {}));
  frames_on_worker(worker, 2);
  worker.shown().world().settings.gravity = Vec3(0.0, -2.0, 0.0);
  worker.exchange(VertexDrag(), 1.0);
  worker.resume_from(1);
  frames_on_worker(worker, 1);
  SimulationSession reference(file.path(), {});
  reference.advance_frame();
  reference.world().settings.gravity = Vec3(0.0, -2.0, 0.0);
  reference.advance_frame();
  expect_same_state(worker.shown(), reference);
}

}  // namespace
}  // namespace weft
