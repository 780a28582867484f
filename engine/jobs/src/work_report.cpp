#include "penumbra/jobs/work_report.h"

namespace penumbra::jobs {
namespace {
thread_local WorkCounter* current = nullptr;
}  // namespace

void report_work(std::uint64_t done, std::uint64_t skipped) {
  WorkCounter* c = current;
  if (!c) return;
  c->done.fetch_add(done, std::memory_order_relaxed);
  c->skipped.fetch_add(skipped, std::memory_order_relaxed);
  c->reported.store(true, std::memory_order_relaxed);
}

WorkScope::WorkScope(WorkCounter* counter) : previous_(current) {
  current = counter;
}

WorkScope::~WorkScope() {
  current = previous_;
}

}  // namespace penumbra::jobs
