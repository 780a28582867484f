// Deferred structural changes: create, destroy, add and remove, recorded while systems run and
// applied by apply_commands() at a sync point.
//
// Determinism: every command carries a sort key and a sequence number. The job graph gives each
// (system, chunk) pair its own key, and a CommandWriter numbers the commands it records, so
// apply_commands() replays them in the same order whichever worker recorded them and however
// many workers there were. Entities created through a buffer get real handles in that order.
//
// A handle returned by CommandWriter::create() is a placeholder (Entity::is_pending()): it is
// valid in commands of the same buffer until the next apply, and must not be stored elsewhere.
//
// Threading: a CommandBuffer belongs to one thread at a time (the job graph keeps one per
// worker). apply_commands() needs exclusive access to the world and the buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "penumbra/ecs/entity.h"
#include "penumbra/ecs/type_info.h"

namespace penumbra::ecs {

class World;

class CommandBuffer {
 public:
  enum class Op : std::uint8_t { kCreate, kDestroy, kAdd, kRemove };
  struct Command {
    std::uint64_t key;
    std::uint32_t seq;
    Op op;
    TypeId type;
    Entity target;
    void* payload;  // kAdd: a live value of `type`, owned by this buffer until applied
  };

  // `id` tells placeholders of different buffers apart (0..255).
  explicit CommandBuffer(std::uint32_t id = 0);
  ~CommandBuffer();
  CommandBuffer(CommandBuffer&&) noexcept;
  CommandBuffer& operator=(CommandBuffer&&) = delete;
  CommandBuffer(const CommandBuffer&) = delete;

  std::uint32_t id() const { return id_; }
  bool empty() const { return commands_.empty(); }
  std::size_t size() const { return commands_.size(); }
  std::span<const Command> commands() const { return commands_; }
  // Drops every recorded command without applying it.
  void clear();

  // Low-level recording; prefer CommandWriter.
  Entity record_create(std::uint64_t key, std::uint32_t seq);
  void record(std::uint64_t key, std::uint32_t seq, Op op, Entity target, TypeId type = 0,
              void* payload = nullptr);
  // Storage for a kAdd payload of `info`'s type, owned by this buffer.
  void* allocate_payload(const TypeInfo& info);

 private:
  void release_payloads();

  std::uint32_t id_;
  std::uint32_t created_ = 0;
  std::vector<Command> commands_;
  struct Block {
    std::byte* data;
    std::size_t used;
    std::size_t capacity;
  };
  std::vector<Block> blocks_;
};

// Records commands into one buffer under one sort key, numbering them in call order.
class CommandWriter {
 public:
  CommandWriter(CommandBuffer& buffer, std::uint64_t key) : buffer_(&buffer), key_(key) {}

  Entity create() { return buffer_->record_create(key_, seq_++); }
  void destroy(Entity e) { buffer_->record(key_, seq_++, CommandBuffer::Op::kDestroy, e); }
  template <class T>
  void add(Entity e, T value) {
    const TypeId type = type_id<T>();
    void* payload = buffer_->allocate_payload(type_info(type));
    ::new (payload) T(std::move(value));
    buffer_->record(key_, seq_++, CommandBuffer::Op::kAdd, e, type, payload);
  }
  template <class T>
  void remove(Entity e) {
    buffer_->record(key_, seq_++, CommandBuffer::Op::kRemove, e, type_id<T>());
  }

 private:
  CommandBuffer* buffer_;
  std::uint64_t key_;
  std::uint32_t seq_ = 0;
};

struct ApplyStats {
  std::size_t applied = 0;
  // Commands whose target was dead or stale by the time they ran (e.g. two systems destroyed
  // the same entity, or a component was added to a destroyed one): skipped, never an error.
  std::size_t dropped = 0;
  std::size_t created = 0;
};

// Applies every command of `buffers` in (key, seq, buffer id) order, then clears the buffers.
ApplyStats apply_commands(World& world, std::span<CommandBuffer* const> buffers);

}  // namespace penumbra::ecs
