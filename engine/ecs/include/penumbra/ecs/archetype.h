// Archetype tables: the component storage.
//
// Why archetypes (not sparse sets): every lighting system iterates entities that share a fixed
// set of components (receivers with transform + transfer vector, blockers with sphere sets).
// An archetype stores all entities with exactly one component set, in chunks of up to
// chunk_capacity() rows; inside a chunk each component is one contiguous array (SoA). A query
// over several components therefore walks plain arrays with no per-entity indirection, and a
// chunk is the natural unit of a parallel-for and of change detection.
//
// Chunk layout: [Entity x capacity][column 0 x capacity][column 1 x capacity]..., each array
// 64-byte aligned, one allocation of about kTargetChunkBytes. Rows are dense: every chunk but
// the last is full, and removal swaps the archetype's last row into the hole.
//
// Change detection is per chunk and per column (as in Unity DOTS): changed_tick(col) is the tick
// of the last write access to that column in that chunk. It is conservative: a chunk counts as
// changed if any row in it may have been written. Systems skip whole unchanged chunks.
//
// Threading: structural operations (push_back, swap_remove, edges) are for the owning World on
// one thread. Different chunks, or different columns of one chunk, may be written concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "penumbra/ecs/entity.h"
#include "penumbra/ecs/type_info.h"

namespace penumbra::ecs {

struct RowRef {
  std::uint32_t chunk = 0;
  std::uint32_t row = 0;
};

class Archetype {
 public:
  static constexpr std::size_t kTargetChunkBytes = 64 * 1024;
  static constexpr std::uint32_t kMinRows = 16;
  static constexpr std::uint32_t kMaxRows = 4096;

  Archetype(std::uint32_t id, std::vector<TypeId> sorted_types);
  ~Archetype();
  Archetype(const Archetype&) = delete;
  Archetype& operator=(const Archetype&) = delete;

  std::uint32_t id() const { return id_; }
  const TypeSet& signature() const { return signature_; }
  std::span<const TypeId> types() const { return types_; }
  // Column index of `type`, or -1 when this archetype does not store it.
  int column_of(TypeId type) const { return column_of_[type]; }

  std::uint32_t chunk_capacity() const { return capacity_; }
  std::size_t chunk_count() const { return chunks_.size(); }
  std::size_t size() const { return size_; }
  std::uint32_t chunk_size(std::size_t chunk) const { return chunks_[chunk].count; }

  Entity* entities(std::size_t chunk) const {
    return reinterpret_cast<Entity*>(chunks_[chunk].block);
  }
  void* column(std::size_t chunk, int col) const {
    return chunks_[chunk].block + column_offset_[col];
  }
  void* slot(RowRef r, int col) const {
    return static_cast<std::byte*>(column(r.chunk, col)) + r.row * column_size_[col];
  }
  std::uint64_t changed_tick(std::size_t chunk, int col) const {
    return chunks_[chunk].changed[col];
  }
  void mark_changed(std::size_t chunk, int col, std::uint64_t tick) {
    chunks_[chunk].changed[col] = tick;
  }

  // Appends a row for `e` whose component slots are uninitialised: the caller constructs every
  // column. All columns of the chunk are marked changed at `tick`.
  RowRef push_back(Entity e, std::uint64_t tick);
  // Removes the row at `where` by moving the archetype's last row into it. When
  // `destroy_components` is false the caller has already relocated or destroyed them. The
  // hole's chunk is marked changed at `tick` (its rows now hold another entity).
  // Returns the entity that moved into `where`, or kNullEntity when `where` was the last row.
  Entity swap_remove(RowRef where, bool destroy_components, std::uint64_t tick);

  // Transition cache: the archetype reached by adding or removing one type.
  std::unordered_map<TypeId, Archetype*> add_edges;
  std::unordered_map<TypeId, Archetype*> remove_edges;

 private:
  struct Chunk {
    std::byte* block = nullptr;
    std::uint32_t count = 0;
    std::vector<std::uint64_t> changed;
  };

  std::uint32_t id_;
  TypeSet signature_;
  std::vector<TypeId> types_;
  std::vector<const TypeInfo*> infos_;
  std::vector<std::size_t> column_offset_;
  std::vector<std::size_t> column_size_;
  std::vector<std::int16_t> column_of_;  // kMaxTypes entries
  std::uint32_t capacity_ = 0;
  std::size_t block_bytes_ = 0;
  std::size_t size_ = 0;
  std::vector<Chunk> chunks_;
};

}  // namespace penumbra::ecs
