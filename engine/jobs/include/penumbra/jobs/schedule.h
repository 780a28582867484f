// Schedule: systems in registration order, turned into a dependency graph (DAG).
//
// Edges. For systems registered in order a before b, the graph has a -> b when their accesses
// conflict (one writes what the other reads or writes). Readers of the same data get no edge
// and may run together. after()/before() add explicit edges. With Ordering::kExplicit the
// conflict edges are not added: only explicit constraints order systems, and conflicts()
// reports conflicting pairs left with no path between them (the executor then serialises them
// in registration order so a frame stays correct).
//
// Sync points. A system that records deferred structural commands declares it (spawns(),
// structural<T...>()). Before the first later system that touches a declared type (or any
// query system, after spawns()), build() inserts a sync node that applies the commands; one
// more closes the frame if commands may still be pending. A sync node is exclusive: it is
// ordered after everything before it and before everything after it.
//
// The edge list is transitively reduced (no edge implied by a longer path), which is what
// to_dot() draws and what the executor counts down.
//
// Threading: build and modify a schedule on one thread; the Executor runs it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "penumbra/ecs/query.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/system.h"

namespace penumbra::jobs {

class SystemBuilder {
 public:
  explicit SystemBuilder(System& s) : s_(&s) {}
  template <class... Ts>
  SystemBuilder& reads() {
    s_->access.reads |= ecs::type_set<Ts...>();
    return *this;
  }
  template <class... Ts>
  SystemBuilder& writes() {
    s_->access.writes |= ecs::type_set<Ts...>();
    return *this;
  }
  // Chunk systems: skip entities that have any of Ts.
  template <class... Ts>
  SystemBuilder& without() {
    s_->exclude |= ecs::type_set<Ts...>();
    return *this;
  }
  // The system's commands add or remove components of types Ts.
  template <class... Ts>
  SystemBuilder& structural() {
    s_->access.structural |= ecs::type_set<Ts...>();
    return *this;
  }
  // The system's commands create or destroy entities.
  SystemBuilder& spawns() {
    s_->access.spawns = true;
    return *this;
  }
  SystemBuilder& after(std::string name) {
    s_->after.push_back(std::move(name));
    return *this;
  }
  SystemBuilder& before(std::string name) {
    s_->before.push_back(std::move(name));
    return *this;
  }
  System& system() const { return *s_; }

 private:
  System* s_;
};

// A pair of systems whose accesses conflict and that no path in the graph orders.
struct Conflict {
  std::string first, second;
};

class Schedule {
 public:
  enum class Ordering { kRegistration, kExplicit };

  struct Node {
    System* system;  // the registered system, or the schedule-owned sync system
    std::vector<std::uint32_t> successors;    // transitively reduced
    std::vector<std::uint32_t> predecessors;  // transitively reduced
    // Runtime state, owned by the Executor running this schedule.
    std::uint64_t last_run_tick = 0;
    double ns_per_chunk = 0;  // measured, sets the parallel-for grain
  };

  Schedule() = default;
  explicit Schedule(Ordering ordering) : ordering_(ordering) {}
  Schedule(const Schedule&) = delete;
  Schedule& operator=(const Schedule&) = delete;

  // A system run once per frame: f(SystemContext&). Declare its access on the builder.
  template <class F>
  SystemBuilder add_task(std::string name, F f);
  // f(SystemContext&, const ecs::ChunkView<Ts...>&) for every chunk of query<Ts...>.
  // Access is derived from Ts: `T` is written, `const T` read.
  template <class... Ts, class F>
  SystemBuilder add_chunks(std::string name, F f);
  // f(Ts&...) or f(ecs::Entity, Ts&...) for every entity of query<Ts...>.
  template <class... Ts, class F>
  SystemBuilder add_each(std::string name, F f);
  // Deterministic reduction: chunk_fn(const ChunkView<Ts...>&, Acc&) fills one partial per
  // chunk starting from `init`; partials are combined in chunk order by combine(Acc&, const
  // Acc&), and done(SystemContext&, Acc&) receives the total.
  template <class Acc, class... Ts, class ChunkFn, class Combine, class Done>
  SystemBuilder add_reduce(std::string name, Acc init, ChunkFn chunk_fn, Combine combine,
                           Done done);
  // An explicit sync point at this position.
  void add_sync_point(std::string name = "sync");

  // Pauses or resumes the system called `name` (not a sync point) from the next frame on, between
  // frames only; false when there is none. A paused system keeps its place in the graph and runs
  // nothing: what it writes keeps its last values, and its "changed since my last run" stamp
  // stays at its last real run.
  bool set_paused(std::string_view name, bool paused);
  bool paused(std::string_view name) const;

  // Builds the graph (done by the executor when systems changed). Throws std::invalid_argument
  // on unknown names in after()/before(), duplicate names, or a cycle.
  void build();
  bool built() const { return built_; }
  Ordering ordering() const { return ordering_; }

  // In execution-stamp order (a topological order); valid after build().
  std::vector<Node>& nodes() { return nodes_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  std::vector<Conflict> conflicts() const { return conflicts_; }
  // Graphviz DOT of the built graph: one box per system (with its reads and writes), a
  // diamond per sync point, the reduced edges.
  std::string to_dot() const;

 private:
  System& push(std::string name, System::Kind kind);

  Ordering ordering_ = Ordering::kRegistration;
  std::vector<std::unique_ptr<System>> systems_;  // registration order, sync points included
  std::vector<std::unique_ptr<System>> auto_syncs_;
  std::vector<Node> nodes_;
  std::vector<Conflict> conflicts_;
  bool built_ = false;
};

// ---------------------------------------------------------------------------------------------

namespace detail {
// A query bound lazily to whichever world the system runs on.
template <class... Ts>
struct QuerySlot {
  ecs::World* world = nullptr;
  std::unique_ptr<ecs::Query<Ts...>> query;

  ecs::Query<Ts...>& bind(ecs::World& w, const ecs::TypeSet& exclude) {
    if (!query || world != &w || query->excluded() != exclude) {
      world = &w;
      query = std::make_unique<ecs::Query<Ts...>>(w);
      query->without(exclude);
    }
    return *query;
  }
};

template <class... Ts>
std::shared_ptr<QuerySlot<Ts...>> make_query_system(System& s) {
  auto slot = std::make_shared<QuerySlot<Ts...>>();
  ((std::is_const_v<Ts> ? s.access.reads.set(ecs::type_id<Ts>())
                        : s.access.writes.set(ecs::type_id<Ts>())),
   ...);
  s.prepare = [slot](ecs::World& w, const ecs::TypeSet& exclude, std::size_t& entities) {
    auto& q = slot->bind(w, exclude);
    const std::size_t n = q.prepare();
    entities = q.entity_count();
    return n;
  };
  return slot;
}
}  // namespace detail

template <class F>
SystemBuilder Schedule::add_task(std::string name, F f) {
  System& s = push(std::move(name), System::Kind::kTask);
  s.run = std::move(f);
  return SystemBuilder(s);
}

template <class... Ts, class F>
SystemBuilder Schedule::add_chunks(std::string name, F f) {
  System& s = push(std::move(name), System::Kind::kChunks);
  auto slot = detail::make_query_system<Ts...>(s);
  s.run_chunk = [slot, f = std::move(f)](SystemContext& ctx) {
    f(ctx, slot->query->chunk(ctx.chunk(), ctx.tick()));
  };
  return SystemBuilder(s);
}

template <class... Ts, class F>
SystemBuilder Schedule::add_each(std::string name, F f) {
  return add_chunks<Ts...>(std::move(name),
                           [f = std::move(f)](SystemContext&, const ecs::ChunkView<Ts...>& c) {
                             const std::uint32_t rows = c.size();
                             auto spans = std::make_tuple(c.template get<Ts>()...);
                             if constexpr (std::is_invocable_v<const F&, ecs::Entity, Ts&...>) {
                               const auto ents = c.entities();
                               for (std::uint32_t r = 0; r < rows; ++r)
                                 f(ents[r], std::get<std::span<Ts>>(spans)[r]...);
                             } else {
                               for (std::uint32_t r = 0; r < rows; ++r)
                                 f(std::get<std::span<Ts>>(spans)[r]...);
                             }
                           });
}

template <class Acc, class... Ts, class ChunkFn, class Combine, class Done>
SystemBuilder Schedule::add_reduce(std::string name, Acc init, ChunkFn chunk_fn, Combine combine,
                                   Done done) {
  System& s = push(std::move(name), System::Kind::kChunks);
  auto slot = detail::make_query_system<Ts...>(s);
  auto partials = std::make_shared<std::vector<Acc>>();
  auto prepare = std::move(s.prepare);
  s.prepare = [prepare, partials, init](ecs::World& w, const ecs::TypeSet& ex, std::size_t& n) {
    const std::size_t chunks = prepare(w, ex, n);
    partials->assign(chunks, init);
    return chunks;
  };
  s.run_chunk = [slot, partials, chunk_fn = std::move(chunk_fn)](SystemContext& ctx) {
    chunk_fn(slot->query->chunk(ctx.chunk(), ctx.tick()), (*partials)[ctx.chunk()]);
  };
  s.finish = [partials, init, combine = std::move(combine),
              done = std::move(done)](SystemContext& ctx) {
    Acc total = init;
    for (const Acc& p : *partials) combine(total, p);  // fixed order: chunk order
    done(ctx, total);
  };
  return SystemBuilder(s);
}

}  // namespace penumbra::jobs
