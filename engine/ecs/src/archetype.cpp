#include "penumbra/ecs/archetype.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstdlib>
#include <cstring>

namespace penumbra::ecs {
namespace {
constexpr std::size_t kChunkAlign = 64;
std::size_t align_up(std::size_t v) {
  return (v + kChunkAlign - 1) & ~(kChunkAlign - 1);
}
}  // namespace

Archetype::Archetype(std::uint32_t id, std::vector<TypeId> sorted_types)
    : id_(id), types_(std::move(sorted_types)), column_of_(kMaxTypes, -1) {
  std::size_t row_bytes = sizeof(Entity);
  for (std::size_t c = 0; c < types_.size(); ++c) {
    const TypeInfo& info = type_info(types_[c]);
    assert(info.align <= kChunkAlign && "component alignment above 64 bytes is not supported");
    signature_.set(types_[c]);
    column_of_[types_[c]] = static_cast<std::int16_t>(c);
    infos_.push_back(&info);
    column_size_.push_back(info.size);
    row_bytes += info.size;
  }
  // Rows per chunk: as many as fit the target size, a multiple of 16, within [kMinRows, kMaxRows].
  std::size_t rows = kTargetChunkBytes / row_bytes;
  rows = std::clamp<std::size_t>(rows & ~std::size_t{15}, kMinRows, kMaxRows);
  capacity_ = static_cast<std::uint32_t>(rows);
  std::size_t offset = align_up(sizeof(Entity) * rows);
  for (std::size_t c = 0; c < types_.size(); ++c) {
    column_offset_.push_back(offset);
    offset = align_up(offset + column_size_[c] * rows);
  }
  block_bytes_ = std::max<std::size_t>(offset, kChunkAlign);
}

Archetype::~Archetype() {
  for (std::size_t k = 0; k < chunks_.size(); ++k) {
    for (std::size_t c = 0; c < types_.size(); ++c) {
      for (std::uint32_t r = 0; r < chunks_[k].count; ++r) {
        infos_[c]->destroy(slot({static_cast<std::uint32_t>(k), r}, static_cast<int>(c)));
      }
    }
    std::free(chunks_[k].block);
  }
}

RowRef Archetype::push_back(Entity e, std::uint64_t tick) {
  if (chunks_.empty() || chunks_.back().count == capacity_) {
    Chunk chunk;
    chunk.block = static_cast<std::byte*>(std::aligned_alloc(kChunkAlign, block_bytes_));
    if (chunk.block == nullptr) throw std::bad_alloc();
    chunk.changed.assign(types_.size(), tick);
    chunks_.push_back(std::move(chunk));
  }
  Chunk& chunk = chunks_.back();
  const RowRef ref{static_cast<std::uint32_t>(chunks_.size() - 1), chunk.count};
  entities(ref.chunk)[ref.row] = e;
  std::fill(chunk.changed.begin(), chunk.changed.end(), tick);
  ++chunk.count;
  ++size_;
  return ref;
}

Entity Archetype::swap_remove(RowRef where, bool destroy_components, std::uint64_t tick) {
  assert(where.chunk < chunks_.size() && where.row < chunks_[where.chunk].count);
  if (destroy_components) {
    for (std::size_t c = 0; c < types_.size(); ++c) infos_[c]->destroy(slot(where, int(c)));
  }
  const std::uint32_t last_chunk = static_cast<std::uint32_t>(chunks_.size() - 1);
  const RowRef last{last_chunk, chunks_[last_chunk].count - 1};
  Entity moved = kNullEntity;
  if (where.chunk != last.chunk || where.row != last.row) {
    for (std::size_t c = 0; c < types_.size(); ++c) {
      void* dst = slot(where, int(c));
      void* src = slot(last, int(c));
      if (infos_[c]->trivially_relocatable) {
        std::memcpy(dst, src, column_size_[c]);
      } else {
        infos_[c]->relocate(dst, src);
      }
      chunks_[where.chunk].changed[c] = tick;
    }
    moved = entities(last.chunk)[last.row];
    entities(where.chunk)[where.row] = moved;
  }
  --chunks_[last_chunk].count;
  --size_;
  if (chunks_[last_chunk].count == 0) {
    std::free(chunks_[last_chunk].block);
    chunks_.pop_back();
  }
  return moved;
}

}  // namespace penumbra::ecs
