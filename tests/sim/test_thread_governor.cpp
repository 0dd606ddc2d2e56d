// The thread governor (sim/thread_governor.hpp) driven by synthetic step times: it keeps the
// requested count where that is faster, falls back to one thread where one is faster (a core
// taken by another process), returns when the other process leaves, probes again when the step
// cost changes regime, and is not flipped by noise, trends or a jump within a probe.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "sim/thread_governor.hpp"

namespace weft {
namespace {

struct GovernedRun {
  int single_thread_steps = 0;
};

// Steps the governor `steps` times; `cost(step, threads)` is the step's wall time.
GovernedRun run(ThreadGovernor& governor, int steps, const std::function<double(int, int)>& cost) {
  GovernedRun result;
  for (int s = 0; s < steps; ++s) {
    const int threads = governor.threads();
    result.single_thread_steps += threads == 1;
    governor.record(cost(s, threads));
  }
  return result;
}

TEST(ThreadGovernor, OneRequestedThreadIsNeverProbed) {
  ThreadGovernor governor;
  governor.set_requested(1);
  const GovernedRun result = run(governor, 5000, [](int, int threads) { return threads == 1 ? 2.0 : 1.0; });
  EXPECT_EQ(result.single_thread_steps, 5000);
}

TEST(ThreadGovernor, KeepsTheRequestedThreadsWhereTheyAreFasterAndProbesRarely) {
  ThreadGovernor governor;
  governor.set_requested(2);
  const GovernedRun result = run(governor, 20000, [](int, int threads) { return threads == 1 ? 1.9 : 1.0; });
  EXPECT_EQ(governor.current(), 2);
  // Probes back off to one every longest_wait steps: probes (half their steps on one thread)
  // after 20, 40, ..., 2560, then every 2560 steps.
  EXPECT_GT(result.single_thread_steps, 0);
  EXPECT_LT(result.single_thread_steps, 0.005 * 20000);
}

TEST(ThreadGovernor, FallsBackToOneThreadWhileACoreIsTakenAndReturnsAfter) {
  ThreadGovernor governor;
  governor.set_requested(2);
  // Steps 0-2999: another process holds a core, two threads take 1.3 s against one thread's 1.0;
  // from step 3000 the core is free again and two threads take 0.55 s.
  const auto cost = [](int step, int threads) {
    if (threads == 1) return 1.0;
    return step < 3000 ? 1.3 : 0.55;
  };
  const GovernedRun busy = run(governor, 3000, cost);
  EXPECT_EQ(governor.current(), 1);
  // The first probe (after first_probe_after steps) switches; afterwards two threads run only
  // in probes.
  EXPECT_GT(busy.single_thread_steps,
            3000 - ThreadGovernor::first_probe_after - 20 * ThreadGovernor::probe_steps);

  // Back on two threads: more consecutive two-thread steps than a probe holds.
  int steps_until_back = 0, consecutive = 0;
  while (consecutive <= ThreadGovernor::probe_steps && steps_until_back < 3 * ThreadGovernor::longest_wait) {
    const int threads = governor.threads();
    consecutive = threads == 2 ? consecutive + 1 : 0;
    governor.record(cost(3000 + steps_until_back, threads));
    ++steps_until_back;
  }
  EXPECT_LE(steps_until_back, ThreadGovernor::longest_wait + 3 * ThreadGovernor::probe_steps);
  const GovernedRun free =
      run(governor, 1000, [&](int step, int threads) { return cost(4000 + step, threads); });
  EXPECT_EQ(governor.current(), 2);
  // After a switch the probes back off again from first_probe_after: at most six in 1000 steps
  // (20, 40, ..., 640 steps apart), half of each on one thread.
  EXPECT_LE(free.single_thread_steps, 6 * ThreadGovernor::probe_steps / 2);
}

TEST(ThreadGovernor, AFallingStepCostDoesNotPassForAFasterCount) {
  // Step costs falling 8% a step over the first 60 steps (a cloth leaving a hard contact), two
  // threads 1.3x faster throughout. A probe compared only with the steps before it would see one
  // thread as faster (1.3 x 0.92^5 = 0.86); within the probe's blocks the trend cancels.
  ThreadGovernor governor;
  governor.set_requested(2);
  const GovernedRun result = run(governor, 200, [](int step, int threads) {
    return std::pow(0.92, std::min(step, 60)) * (threads == 1 ? 1.3 : 1.0);
  });
  EXPECT_EQ(governor.current(), 2);
  EXPECT_LE(result.single_thread_steps, 3 * ThreadGovernor::probe_steps);
}

TEST(ThreadGovernor, AJumpInStepCostDuringAProbeDoesNotSwitch) {
  // Two threads 1.2x faster throughout (within clear_margin, so the probe does not end after its
  // first block); the step cost jumps six-fold (a cloth meeting the sphere) in the middle of the
  // first probe. One block sees the cheap step on one thread against expensive ones on two; the
  // median of the blocks does not.
  ThreadGovernor governor;
  governor.set_requested(2);
  const int jump = ThreadGovernor::first_probe_after + ThreadGovernor::probe_steps / 2 - 1;
  const GovernedRun result =
      run(governor, ThreadGovernor::first_probe_after + ThreadGovernor::probe_steps,
          [&](int step, int threads) { return (step < jump ? 1.0 : 6.0) * (threads == 1 ? 1.2 : 1.0); });
  EXPECT_EQ(result.single_thread_steps, ThreadGovernor::probe_steps / 2);  // the probe ran, on steps 20-31
  EXPECT_EQ(governor.current(), 2);
}

TEST(ThreadGovernor, AChangeOfRegimeIsProbedAtOnce) {
  // Light steps for 2,000 steps where both counts cost the same (the probes keep two threads and
  // back off to waits of 640 and more), then steps six times heavier on which one thread is 1.3x
  // faster (a shared core matters once a step holds work): the governor probes within
  // first_probe_after + probe_steps steps of the change and switches, instead of waiting out
  // the backed-off interval.
  ThreadGovernor governor;
  governor.set_requested(2);
  const int change = 2000;
  const auto cost = [&](int step, int threads) { return step < change ? 1.0 : (threads == 1 ? 6.0 : 7.8); };
  run(governor, change, cost);
  EXPECT_EQ(governor.current(), 2);
  const auto heavy = [&](int step, int threads) { return cost(change + step, threads); };
  run(governor, ThreadGovernor::first_probe_after + ThreadGovernor::probe_steps, heavy);
  EXPECT_EQ(governor.current(), 1);  // without the regime test, ~600 steps to the next probe
  const GovernedRun after = run(governor, 200, heavy);
  EXPECT_EQ(governor.current(), 1);
  // Two threads only in the probes after 20, 40 and 80 steps.
  EXPECT_GE(after.single_thread_steps, 200 - 3 * ThreadGovernor::probe_steps / 2);
}

TEST(ThreadGovernor, AClearlySlowerOtherCountEndsTheProbeAfterOneBlock) {
  // Two threads 1.85x faster (the 64x64 drape on a free 2-core machine): each probe runs two steps
  // on one thread, not six, and the count stays.
  ThreadGovernor governor;
  governor.set_requested(2);
  const auto cost = [](int, int threads) { return threads == 1 ? 1.85 : 1.0; };
  const GovernedRun first =
      run(governor, ThreadGovernor::first_probe_after + ThreadGovernor::probe_steps, cost);
  EXPECT_EQ(first.single_thread_steps, 2);
  EXPECT_EQ(governor.current(), 2);
  // Later probes likewise, the waits quadrupling (80, 320, 1280 steps, then 2560).
  const GovernedRun later = run(governor, 5000, cost);
  EXPECT_EQ(later.single_thread_steps % 2, 0);
  EXPECT_LE(later.single_thread_steps, 2 * 5);
  EXPECT_EQ(governor.current(), 2);
}

TEST(ThreadGovernor, OneSlowStepInTheFirstBlockDoesNotEndTheProbe) {
  // One thread faster (another process holds a core: two threads 1.0, one 0.8), but the first
  // step of the first probe, on one thread, is slowed five-fold by something else. That block's
  // ratio says keep two threads; its other step does not, so the probe runs on and switches.
  ThreadGovernor governor;
  governor.set_requested(2);
  const int first_probe_step = ThreadGovernor::first_probe_after;
  run(governor, first_probe_step + ThreadGovernor::probe_steps, [&](int step, int threads) {
    if (threads == 2) return 1.0;
    return step == first_probe_step ? 4.0 : 0.8;
  });
  EXPECT_EQ(governor.current(), 1);
}

TEST(ThreadGovernor, NoiseWithinTheMarginDoesNotSwitch) {
  ThreadGovernor governor;
  governor.set_requested(2);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(0.96, 1.04);
  const GovernedRun result = run(governor, 20000, [&](int, int) { return noise(rng); });
  EXPECT_EQ(governor.current(), 2);
  EXPECT_LT(result.single_thread_steps, 0.005 * 20000);
}

TEST(ThreadGovernor, ANewRequestStartsOver) {
  ThreadGovernor governor;
  governor.set_requested(2);
  run(governor, 500, [](int, int threads) { return threads == 1 ? 1.0 : 2.0; });
  EXPECT_EQ(governor.threads(), 1);
  governor.set_requested(4);
  EXPECT_EQ(governor.requested(), 4);
  EXPECT_EQ(governor.threads(), 4);
}

}  // namespace
}  // namespace weft
