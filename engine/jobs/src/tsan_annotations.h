// Happens-before annotations for ThreadSanitizer at the executor's hand-offs through oneTBB.
//
// Debian's libtbb is not instrumented, so TSan cannot see that a task spawned by one thread
// starts after the spawn, or that parallel_for/task_group::wait return after their tasks end.
// The executor marks each hand-off explicitly: release on a token before handing work over,
// acquire on it where the work is picked up. Tokens are per hand-off (per parallel_for call,
// per graph node, per frame), so tasks that run side by side stay unordered and real races
// between them are still reported. No-ops in builds without TSan.
#pragma once

#if defined(PENUMBRA_TSAN)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
namespace penumbra::jobs::tsan {
inline void release(const void* token) {
  __tsan_release(const_cast<void*>(token));
}
inline void acquire(const void* token) {
  __tsan_acquire(const_cast<void*>(token));
}
}  // namespace penumbra::jobs::tsan
#else
namespace penumbra::jobs::tsan {
inline void release(const void*) {}
inline void acquire(const void*) {}
}  // namespace penumbra::jobs::tsan
#endif
