#include "penumbra/ecs/command_buffer.h"

#include <algorithm>
#include <cassert>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <unordered_map>

#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {
constexpr std::size_t kBlockBytes = 64 * 1024;
constexpr std::size_t kCommandAlign = 64;
constexpr std::uint32_t kLocalBits = 24;
}  // namespace

CommandBuffer::CommandBuffer(std::uint32_t id) : id_(id) {
  assert(id < 256);
}

CommandBuffer::~CommandBuffer() {
  clear();
  for (const Block& b : blocks_) std::free(b.data);
}

CommandBuffer::CommandBuffer(CommandBuffer&& other) noexcept
    : id_(other.id_),
      created_(other.created_),
      commands_(std::move(other.commands_)),
      blocks_(std::move(other.blocks_)) {
  other.commands_.clear();
  other.blocks_.clear();
}

void CommandBuffer::release_payloads() {
  for (const Command& c : commands_) {
    if (c.payload != nullptr) type_info(c.type).destroy(c.payload);
  }
}

void CommandBuffer::clear() {
  release_payloads();
  commands_.clear();
  created_ = 0;
  // Keep the first block for reuse: a steady-state frame allocates nothing.
  for (std::size_t i = 1; i < blocks_.size(); ++i) std::free(blocks_[i].data);
  if (!blocks_.empty()) {
    blocks_.resize(1);
    blocks_[0].used = 0;
  }
}

Entity CommandBuffer::record_create(std::uint64_t key, std::uint32_t seq) {
  if (created_ >= (1u << kLocalBits))
    throw std::length_error("CommandBuffer: too many creates before apply");
  const Entity placeholder{(id_ << kLocalBits) | created_++, Entity::kPendingGeneration};
  commands_.push_back({key, seq, Op::kCreate, 0, placeholder, nullptr});
  return placeholder;
}

void CommandBuffer::record(std::uint64_t key, std::uint32_t seq, Op op, Entity target, TypeId type,
                           void* payload) {
  commands_.push_back({key, seq, op, type, target, payload});
}

void* CommandBuffer::allocate_payload(const TypeInfo& info) {
  assert(info.align <= kCommandAlign);
  const std::size_t size =
      (std::max<std::size_t>(info.size, 1) + kCommandAlign - 1) & ~(kCommandAlign - 1);
  if (blocks_.empty() || blocks_.back().used + size > blocks_.back().capacity) {
    const std::size_t capacity = std::max(kBlockBytes, size);
    auto* data = static_cast<std::byte*>(std::aligned_alloc(kCommandAlign, capacity));
    if (data == nullptr) throw std::bad_alloc();
    blocks_.push_back({data, 0, capacity});
  }
  Block& b = blocks_.back();
  void* p = b.data + b.used;
  b.used += size;
  return p;
}

ApplyStats apply_commands(World& world, std::span<CommandBuffer* const> buffers) {
  struct Ref {
    const CommandBuffer::Command* command;
    std::uint32_t buffer;
  };
  std::vector<Ref> order;
  for (CommandBuffer* b : buffers) {
    for (const auto& c : b->commands()) order.push_back({&c, b->id()});
  }
  std::sort(order.begin(), order.end(), [](const Ref& a, const Ref& b) {
    if (a.command->key != b.command->key) return a.command->key < b.command->key;
    if (a.buffer != b.buffer) return a.buffer < b.buffer;
    return a.command->seq < b.command->seq;
  });

  ApplyStats stats;
  std::unordered_map<std::uint64_t, Entity> created;
  auto resolve = [&](Entity e) {
    if (!e.is_pending()) return e;
    auto it = created.find(e.bits());
    return it == created.end() ? kNullEntity : it->second;
  };
  for (const Ref& r : order) {
    const auto& c = *r.command;
    bool ok = true;
    switch (c.op) {
      case CommandBuffer::Op::kCreate:
        created.emplace(c.target.bits(), world.create());
        ++stats.created;
        break;
      case CommandBuffer::Op::kDestroy:
        ok = world.destroy(resolve(c.target));
        break;
      case CommandBuffer::Op::kAdd: {
        const Entity e = resolve(c.target);
        ok = world.alive(e);
        if (ok) world.add_erased(e, c.type, c.payload);
        break;
      }
      case CommandBuffer::Op::kRemove:
        ok = world.remove_erased(resolve(c.target), c.type);
        break;
    }
    if (ok) {
      ++stats.applied;
    } else {
      ++stats.dropped;
    }
  }
  for (CommandBuffer* b : buffers) b->clear();  // destroys the moved-from payloads
  return stats;
}

}  // namespace penumbra::ecs
