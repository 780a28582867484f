#include "penumbra/jobs/executor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "penumbra/ecs/access_check.h"
#include "penumbra/jobs/command_pool.h"
#include "tsan_annotations.h"

namespace penumbra::jobs {
namespace {
using Clock = std::chrono::steady_clock;
std::int64_t ns_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count();
}
int slot() {
  return std::max(0, tbb::this_task_arena::current_thread_index());
}

// Runs f as system s: in builds with assertions, with s's declared access installed for the
// ECS's checks (penumbra/ecs/access_check.h) and isolated, so that this thread, while it waits
// inside s, runs no other system's work under s's declaration.
// Reports of jobs::report_work on this thread go to `work` meanwhile.
template <class F>
void as_system(const System& s, WorkCounter& work, F&& f) {
  const WorkScope work_scope(&work);
  if constexpr (ecs::kAccessChecks) {
    const ecs::DeclaredAccess declared{s.name, &s.access.reads, &s.access.writes};
    ecs::AccessScope scope(s.access.exclusive ? nullptr : &declared);
    tbb::this_task_arena::isolate(f);
  } else {
    f();
  }
}
}  // namespace

struct Executor::Impl {
  int threads;
  std::optional<tbb::global_control> allow;  // lifts TBB's cap when threads > hardware
  tbb::task_arena arena;
  CommandPool commands;
  bool trace_tasks = false;
  std::mutex trace_mutex;
  FrameStats stats;

  // Per frame.
  Schedule* schedule = nullptr;
  ecs::World* world = nullptr;
  std::uint64_t base_tick = 0;
  Clock::time_point frame_start;
  std::unique_ptr<std::atomic<std::uint32_t>[]> pending;
  std::unique_ptr<WorkCounter[]> work;  // per node, this frame
  std::size_t pending_size = 0;
  char frame_join = 0;  // TSan token: every task chain releases it, run() acquires it

  explicit Impl(int t)
      : threads(t > 0 ? t : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))),
        arena(threads) {
    if (threads > static_cast<int>(tbb::this_task_arena::max_concurrency())) {
      allow.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(threads));
    }
  }

  std::uint64_t tick_of(std::uint32_t node) const { return base_tick + 1 + node; }

  void run_node(std::uint32_t k);
  void run_chunks(std::uint32_t k, System& s, std::size_t chunks);
  // Runs node k, then whatever it makes ready: one inline, the rest spawned into `group`.
  void run_from(std::uint32_t k, tbb::task_group* group);
};

void Executor::Impl::run_chunks(std::uint32_t k, System& s, std::size_t chunks) {
  Schedule::Node& node = schedule->nodes()[k];
  const std::uint64_t tick = tick_of(k);
  const std::uint64_t key_base = std::uint64_t{k} << 32;
  auto body = [&](std::size_t first, std::size_t last) {
    for (std::size_t c = first; c < last; ++c) {
      SystemContext ctx(*world, tick, node.last_run_tick, key_base | c, c, &commands);
      as_system(s, work[k], [&] { s.run_chunk(ctx); });
    }
  };
  if (threads == 1 || chunks == 1) {
    const auto t0 = Clock::now();
    body(0, chunks);
    node.ns_per_chunk =
        static_cast<double>(ns_between(t0, Clock::now())) / static_cast<double>(chunks);
    return;
  }
  // Grain: enough chunks per task for about kTargetTaskNs of work, from the last frame.
  std::size_t grain = 1;
  if (node.ns_per_chunk > 0) {
    grain = static_cast<std::size_t>(static_cast<double>(kTargetTaskNs) / node.ns_per_chunk);
    grain = std::clamp<std::size_t>(
        grain, 1, std::max<std::size_t>(1, chunks / static_cast<std::size_t>(threads)));
  }
  std::atomic<std::int64_t> busy_ns{0};
  char fork_token = 0, join_token = 0;  // TSan hand-off tokens for this parallel_for
  tsan::release(&fork_token);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, chunks, grain),
      [&](const tbb::blocked_range<std::size_t>& r) {
        tsan::acquire(&fork_token);
        const auto t0 = Clock::now();
        body(r.begin(), r.end());
        const auto t1 = Clock::now();
        busy_ns.fetch_add(ns_between(t0, t1), std::memory_order_relaxed);
        if (trace_tasks) {
          std::lock_guard lock(trace_mutex);
          stats.tasks.push_back(
              {k, slot(), ns_between(frame_start, t0), ns_between(t0, t1), r.begin(), r.size()});
        }
        tsan::release(&join_token);
      },
      tbb::simple_partitioner());
  tsan::acquire(&join_token);
  node.ns_per_chunk = static_cast<double>(busy_ns.load()) / static_cast<double>(chunks);
}

void Executor::Impl::run_node(std::uint32_t k) {
  Schedule::Node& node = schedule->nodes()[k];
  System& s = *node.system;
  SystemTiming& timing = stats.systems[k];
  const auto t0 = Clock::now();
  timing.thread = slot();
  const std::uint64_t tick = tick_of(k);
  timing.paused = false;
  if (s.paused && s.kind != System::Kind::kSync) {  // Schedule::set_paused: nothing runs
    timing.paused = true;
    timing.start_ns = ns_between(frame_start, t0);
    return;
  }
  switch (s.kind) {
    case System::Kind::kSync: {
      const std::uint64_t saved = world->tick();
      world->set_tick(tick);  // chunks touched by the commands are stamped with this node's tick
      const ecs::ApplyStats applied = commands.apply(*world);
      world->set_tick(saved);
      stats.commands.applied += applied.applied;
      stats.commands.dropped += applied.dropped;
      stats.commands.created += applied.created;
      timing.entities = applied.applied;
      break;
    }
    case System::Kind::kTask: {
      SystemContext ctx(*world, tick, node.last_run_tick, std::uint64_t{k} << 32, 0, &commands);
      as_system(s, work[k], [&] { s.run(ctx); });
      break;
    }
    case System::Kind::kChunks: {
      std::size_t entities = 0;
      std::size_t chunks = 0;
      as_system(s, work[k], [&] { chunks = s.prepare(*world, s.exclude, entities); });
      timing.entities = entities;
      timing.chunks = chunks;
      if (chunks > 0) run_chunks(k, s, chunks);
      if (s.finish) {
        SystemContext ctx(*world, tick, node.last_run_tick, (std::uint64_t{k} << 32) | 0xFFFFFFFFu,
                          0, &commands);
        as_system(s, work[k], [&] { s.finish(ctx); });
      }
      break;
    }
  }
  node.last_run_tick = tick;
  timing.done = work[k].done.load(std::memory_order_relaxed);
  timing.skipped = work[k].skipped.load(std::memory_order_relaxed);
  timing.reported = work[k].reported.load(std::memory_order_relaxed);
  timing.start_ns = ns_between(frame_start, t0);
  timing.duration_ns = ns_between(t0, Clock::now());
}

void Executor::Impl::run_from(std::uint32_t k, tbb::task_group* group) {
  for (;;) {
    run_node(k);
    std::optional<std::uint32_t> next;
    for (std::uint32_t succ : schedule->nodes()[k].successors) {
      if (pending[succ].fetch_sub(1, std::memory_order_acq_rel) != 1) continue;
      if (!next) {
        next = succ;
      } else {
        const void* token = &pending[succ];
        tsan::release(token);
        group->run([this, succ, group, token] {
          tsan::acquire(token);
          run_from(succ, group);
        });
      }
    }
    if (!next) {
      tsan::release(&frame_join);
      return;
    }
    k = *next;
  }
}

Executor::Executor(int threads) : impl_(std::make_unique<Impl>(threads)) {}
Executor::~Executor() = default;

int Executor::threads() const {
  return impl_->threads;
}
void Executor::set_trace_tasks(bool on) {
  impl_->trace_tasks = on;
}
const FrameStats& Executor::last_frame() const {
  return impl_->stats;
}

const FrameStats& Executor::run(Schedule& schedule, ecs::World& world) {
  Impl& m = *impl_;
  if (!schedule.built()) schedule.build();
  auto& nodes = schedule.nodes();
  const std::size_t n = nodes.size();
  m.schedule = &schedule;
  m.world = &world;
  m.base_tick = world.tick();
  m.stats.threads = m.threads;
  m.stats.commands = {};
  m.stats.tasks.clear();
  m.stats.systems.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    m.stats.systems[i] = SystemTiming{};
    m.stats.systems[i].name = nodes[i].system->name;
    m.stats.systems[i].sync = nodes[i].system->kind == System::Kind::kSync;
  }
  if (m.pending_size != n) {
    m.pending = std::make_unique<std::atomic<std::uint32_t>[]>(n);
    m.work = std::make_unique<WorkCounter[]>(n);
    m.pending_size = n;
  }
  for (std::size_t i = 0; i < n; ++i) {
    m.work[i].done.store(0, std::memory_order_relaxed);
    m.work[i].skipped.store(0, std::memory_order_relaxed);
    m.work[i].reported.store(false, std::memory_order_relaxed);
    m.pending[i].store(static_cast<std::uint32_t>(nodes[i].predecessors.size()),
                       std::memory_order_relaxed);
  }
  m.frame_start = Clock::now();
  if (m.threads == 1) {
    // Nodes are stored in a topological order: run them in it, no tasks at all.
    m.arena.execute([&] {
      for (std::uint32_t k = 0; k < n; ++k) m.run_node(k);
    });
  } else {
    m.arena.execute([&] {
      tbb::task_group group;
      for (std::uint32_t k = 0; k < n; ++k) {
        if (!nodes[k].predecessors.empty()) continue;
        const void* token = &m.pending[k];
        tsan::release(token);
        group.run([&m, k, &group, token] {
          tsan::acquire(token);
          m.run_from(k, &group);
        });
      }
      group.wait();
      tsan::acquire(&m.frame_join);
    });
  }
  m.stats.frame_ns = ns_between(m.frame_start, Clock::now());
  // Ticks used this frame: base+1 .. base+n. Writes outside systems until the next frame get
  // base+n+1, newer than every system's last run.
  world.set_tick(m.base_tick + n + 1);
  return m.stats;
}

}  // namespace penumbra::jobs
