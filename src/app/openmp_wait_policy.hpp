#pragma once
// OpenMP threads that wait at a barrier sleep instead of spinning, unless the user chose
// otherwise. libgomp spins by default, which on a node where another process holds a core makes
// two threads 4-20x slower than one (the spinning thread takes the time slice the working one
// needs): the 64x64 drape, 14 frames, 2 threads on the 2-core machine while another build ran,
// 16.2-21.5 s spinning against 5.4-5.7 s sleeping (2026-11-26; docs/performance.md, "Threads").
// libgomp reads OMP_WAIT_POLICY when it loads, before main(), so the process sets it and
// starts itself again; OMP_WAIT_POLICY=active in the environment keeps spinning (a dedicated
// node may gain a little).
namespace weft {

// Call first in main(). Returns only when the policy is already set or the restart failed (then
// the run goes on with libgomp's default).
void prefer_sleeping_openmp_waits(char** argv);

}  // namespace weft
