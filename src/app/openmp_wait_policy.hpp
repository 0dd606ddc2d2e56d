#pragma once
// OpenMP threads that wait at a barrier spin briefly and then sleep, unless the user chose
// otherwise. libgomp spins long by default, which on a node where another process holds a core
// makes two threads many times slower than one: the spinning thread takes the time slice the
// working one needs. Sleeping at once costs a futex wake-up at every parallel region instead,
// which makes two threads slower than one even on a quiet machine; a short spin
// (GOMP_SPINCOUNT=1000) first catches the next region's start and costs little beside another
// process (docs/performance.md, "Threads", has the measurements).
// libgomp reads OMP_WAIT_POLICY and GOMP_SPINCOUNT when it loads, before main(), so the process
// sets OMP_WAIT_POLICY=passive and GOMP_SPINCOUNT=1000 (each unless the environment has it) and
// starts itself again; OMP_WAIT_POLICY set in the environment leaves both as they are
// (OMP_WAIT_POLICY=active keeps spinning: a dedicated node may gain a little).
namespace weft {

// Call first in main(). Returns only when the policy is already set or the restart failed (then
// the run goes on with libgomp's default).
void prefer_sleeping_openmp_waits(char** argv);

}  // namespace weft
