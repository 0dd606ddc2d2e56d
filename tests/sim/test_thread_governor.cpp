// The thread governor (sim/thread_governor.hpp) driven by synthetic step times: it keeps the
// requested count where that is faster, falls back to one thread where one is faster (a core
// taken by another process), returns when the other process leaves, and is not flipped by noise.
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
  int last_threads = 0;
};

// Steps the governor `steps` times; `cost(step, threads)` is the step's wall time.
GovernedRun run(ThreadGovernor& governor, int steps, const std::function<double(int, int)>& cost) {
  GovernedRun result;
  for (int s = 0; s < steps; ++s) {
    const int threads = governor.threads();
    result.single_thread_steps += threads == 1;
    result.last_threads = threads;
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
  EXPECT_EQ(result.last_threads, 2);
  // Probes back off to one every longest_wait steps: 5-step probes after 20, 40, ..., 2560, then
  // every 2560 steps.
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
  EXPECT_EQ(busy.last_threads, 1);
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
  EXPECT_EQ(free.last_threads, 2);
  // After a switch the probes back off again from first_probe_after: at most six in 1000 steps
  // (20, 40, ..., 640 steps apart).
  EXPECT_LE(free.single_thread_steps, 6 * ThreadGovernor::probe_steps);
}

TEST(ThreadGovernor, AFallingStepCostDoesNotPassForAFasterCount) {
  // Step costs falling 8% a step over the first 60 steps (a cloth leaving a hard contact), two
  // threads 1.3x faster throughout. A probe compared only with the steps before it would see one
  // thread as faster (1.3 x 0.92^5 = 0.86); against the steps before and after it, it does not.
  ThreadGovernor governor;
  governor.set_requested(2);
  const GovernedRun result = run(governor, 200, [](int step, int threads) {
    return std::pow(0.92, std::min(step, 60)) * (threads == 1 ? 1.3 : 1.0);
  });
  EXPECT_EQ(result.last_threads, 2);
  EXPECT_LE(result.single_thread_steps, 3 * ThreadGovernor::probe_steps);
}

TEST(ThreadGovernor, NoiseWithinTheMarginDoesNotSwitch) {
  ThreadGovernor governor;
  governor.set_requested(2);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(0.96, 1.04);
  const GovernedRun result = run(governor, 20000, [&](int, int) { return noise(rng); });
  EXPECT_EQ(result.last_threads, 2);
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
