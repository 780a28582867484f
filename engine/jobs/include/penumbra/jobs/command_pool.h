// One ecs::CommandBuffer per worker thread, applied together at sync points.
//
// Threading: local() is safe from any thread (each thread gets its own buffer); apply() and
// pending() need all workers to be idle (sync points are exclusive in the graph).
#pragma once

#include <cstddef>
#include <memory>

#include "penumbra/ecs/command_buffer.h"

namespace penumbra::jobs {

class CommandPool {
 public:
  CommandPool();
  ~CommandPool();
  CommandPool(const CommandPool&) = delete;
  CommandPool& operator=(const CommandPool&) = delete;

  ecs::CommandBuffer& local();
  // Applies every buffer's commands in (key, seq) order; see ecs::apply_commands.
  ecs::ApplyStats apply(ecs::World& world);
  std::size_t pending() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::jobs
