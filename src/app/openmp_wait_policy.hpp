#pragma once
// OpenMP threads that wait at a barrier spin briefly and then sleep, unless the user chose
// otherwise. libgomp spins long by default, which on a node where another process holds a core
// makes two threads 4-20x slower than one (the spinning thread takes the time slice the working
// one needs): the 64x64 drape, 14 frames, 2 threads on the 2-core machine while another build
// ran, 16.2-21.5 s spinning against 5.4-5.7 s sleeping (2026-11-26; docs/performance.md,
// "Threads"). Sleeping at once costs a futex wake-up at every parallel region instead, which on
// a quiet machine made the 64x64 drape slower on two threads than on one (28.8 s against 22 s);
// a spin of GOMP_SPINCOUNT=1000 first catches the next region's start (11.9 s) and costs little
// beside another process (with the thread governor, 24.0 s against 22.7 s on one thread).
// libgomp reads OMP_WAIT_POLICY and GOMP_SPINCOUNT when it loads, before main(), so the process
// sets OMP_WAIT_POLICY=passive and GOMP_SPINCOUNT=1000 (each unless the environment has it) and
// starts itself again; OMP_WAIT_POLICY set in the environment leaves both as they are
// (OMP_WAIT_POLICY=active keeps spinning: a dedicated node may gain a little).
namespace weft {

// Call first in main(). Returns only when the policy is already set or the restart failed (then
// the run goes on with libgomp's default).
void prefer_sleeping_openmp_waits(char** argv);

}  // namespace weft
