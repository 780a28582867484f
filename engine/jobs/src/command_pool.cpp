#include "penumbra/jobs/command_pool.h"

#include <atomic>
#include <stdexcept>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "penumbra/jobs/system.h"

namespace penumbra::jobs {

struct CommandPool::Impl {
  std::atomic<std::uint32_t> next_id{0};
  tbb::enumerable_thread_specific<ecs::CommandBuffer> buffers{
      [this] { return ecs::CommandBuffer(next_id.fetch_add(1)); }};
};

CommandPool::CommandPool() : impl_(std::make_unique<Impl>()) {}
CommandPool::~CommandPool() = default;

ecs::CommandBuffer& CommandPool::local() {
  return impl_->buffers.local();
}

ecs::ApplyStats CommandPool::apply(ecs::World& world) {
  std::vector<ecs::CommandBuffer*> all;
  for (auto& b : impl_->buffers) all.push_back(&b);
  return ecs::apply_commands(world, all);
}

std::size_t CommandPool::pending() const {
  std::size_t n = 0;
  for (const auto& b : impl_->buffers) n += b.size();
  return n;
}

ecs::CommandWriter& SystemContext::commands() {
  if (!writer_) {
    if (pool_ == nullptr)
      throw std::logic_error(
          "SystemContext::commands(): no command pool (system run outside an Executor)");
    writer_.emplace(pool_->local(), command_key_);
  }
  return *writer_;
}

}  // namespace penumbra::jobs
