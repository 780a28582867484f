// A system: a named piece of per-frame work with a declared Access.
//
// Kinds:
//  - task:   run(ctx) once per frame on one worker.
//  - chunks: prepare() lists the chunks of the system's query, run_chunk(ctx) is called once
//            per chunk (in parallel, several chunks per task), then finish(ctx) once. Use
//            finish with per-chunk partial results for reductions that must not depend on the
//            number of threads (see Schedule::add_reduce).
//  - sync:   applies deferred structural commands (inserted by the Schedule).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/ecs/command_buffer.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/access.h"
#include "penumbra/jobs/work_report.h"

namespace penumbra::jobs {

class CommandPool;

// What a system sees while it runs. One context per task-system run or per chunk.
class SystemContext {
 public:
  SystemContext(ecs::World& world, std::uint64_t tick, std::uint64_t last_run_tick,
                std::uint64_t command_key, std::size_t chunk, CommandPool* pool)
      : world_(&world),
        tick_(tick),
        last_run_tick_(last_run_tick),
        command_key_(command_key),
        chunk_(chunk),
        pool_(pool) {}

  ecs::World& world() const { return *world_; }
  // Stamp of this run: writes are marked with it (ChunkView::get, World::get_mut inside
  // systems is not stamped with it: prefer queries).
  std::uint64_t tick() const { return tick_; }
  // Stamp of this system's previous run, 0 before the first: "changed since last run" is
  // ChunkView::changed_since<T>(last_run_tick()).
  std::uint64_t last_run_tick() const { return last_run_tick_; }
  // Chunk index within the system's query (0 for task systems).
  std::size_t chunk() const { return chunk_; }
  // Deferred structural changes, recorded in this worker's buffer and applied at the next
  // sync point in a deterministic order. Declare them (SystemBuilder::spawns / structural).
  ecs::CommandWriter& commands();
  // This frame's items done and skipped because nothing they read changed (work_report.h).
  void report_work(std::uint64_t done, std::uint64_t skipped) const {
    jobs::report_work(done, skipped);
  }

 private:
  ecs::World* world_;
  std::uint64_t tick_;
  std::uint64_t last_run_tick_;
  std::uint64_t command_key_;
  std::size_t chunk_;
  CommandPool* pool_;
  std::optional<ecs::CommandWriter> writer_;
};

struct System {
  enum class Kind { kTask, kChunks, kSync };

  std::string name;
  Kind kind = Kind::kTask;
  Access access;
  ecs::TypeSet exclude;            // chunk systems: archetypes with any of these are skipped
  std::vector<std::string> after;  // explicit ordering constraints, by system name
  std::vector<std::string> before;

  std::function<void(SystemContext&)> run;  // kTask
  // kChunks: prepare returns the number of chunks and the number of entities in them.
  std::function<std::size_t(ecs::World&, const ecs::TypeSet& exclude, std::size_t& entities)>
      prepare;
  std::function<void(SystemContext&)> run_chunk;
  std::function<void(SystemContext&)> finish;  // optional
  // Set between frames (Schedule::set_paused): the node still orders its neighbours but runs
  // nothing, so what it writes keeps its last values (a debug switch: "freeze this system").
  bool paused = false;
};

}  // namespace penumbra::jobs
