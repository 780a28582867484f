#include "penumbra/ecs/world.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace penumbra::ecs {

World::World() : resources_(kMaxTypes) {
  empty_ = &archetype_for(TypeSet{});
}

World::~World() = default;

Archetype& World::archetype_for(const TypeSet& signature) {
  if (auto it = by_signature_.find(signature); it != by_signature_.end()) return *it->second;
  std::vector<TypeId> types;
  for (std::size_t t = 0; t < kMaxTypes; ++t) {
    if (signature.test(t)) types.push_back(static_cast<TypeId>(t));
  }
  auto archetype =
      std::make_unique<Archetype>(static_cast<std::uint32_t>(archetype_storage_.size()), types);
  Archetype* raw = archetype.get();
  archetype_storage_.push_back(std::move(archetype));
  archetype_list_.push_back(raw);
  by_signature_.emplace(signature, raw);
  return *raw;
}

Archetype& World::neighbour(Archetype& from, TypeId type, bool adding) {
  auto& edges = adding ? from.add_edges : from.remove_edges;
  if (auto it = edges.find(type); it != edges.end()) return *it->second;
  TypeSet sig = from.signature();
  sig.set(type, adding);
  Archetype& to = archetype_for(sig);
  edges.emplace(type, &to);
  return to;
}

Entity World::allocate_entity() {
  std::uint32_t index;
  if (!free_.empty()) {
    index = free_.back();
    free_.pop_back();
  } else {
    if (slots_.size() >= Entity::kInvalidIndex)
      throw std::length_error("penumbra::ecs: out of entity slots");
    index = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  ++live_;
  ++structure_version_;
  return Entity{index, slots_[index].generation};
}

const World::Slot* World::live_slot(Entity e) const {
  if (e.index >= slots_.size()) return nullptr;
  const Slot& s = slots_[e.index];
  if (s.archetype == nullptr || s.generation != e.generation) return nullptr;
  return &s;
}

bool World::alive(Entity e) const {
  return live_slot(e) != nullptr;
}

Entity World::create() {
  check_structural("create");
  const Entity e = allocate_entity();
  Slot& s = slots_[e.index];
  s.archetype = empty_;
  s.row = empty_->push_back(e, tick_);
  return e;
}

Entity World::create_erased(std::span<const TypeId> types, std::span<void* const> values) {
  check_structural("create_with");
  assert(types.size() == values.size());
  TypeSet sig;
  for (TypeId t : types) {
    assert(!sig.test(t) && "create_with: a component type appears twice");
    sig.set(t);
  }
  Archetype& a = archetype_for(sig);
  const Entity e = allocate_entity();
  Slot& s = slots_[e.index];
  s.archetype = &a;
  s.row = a.push_back(e, tick_);
  for (std::size_t i = 0; i < types.size(); ++i) {
    type_info(types[i]).move_construct(a.slot(s.row, a.column_of(types[i])), values[i]);
  }
  return e;
}

bool World::destroy(Entity e) {
  check_structural("destroy");
  const Slot* found = live_slot(e);
  if (found == nullptr) return false;
  Slot& s = slots_[e.index];
  const Entity moved = s.archetype->swap_remove(s.row, /*destroy_components=*/true, tick_);
  if (!moved.is_null()) slots_[moved.index].row = s.row;
  s.archetype = nullptr;
  // Retire the slot rather than let its generation wrap into a value a stale handle may hold.
  if (s.generation + 1 < Entity::kPendingGeneration) {
    ++s.generation;
    free_.push_back(e.index);
  } else {
    s.generation = Entity::kPendingGeneration;
  }
  --live_;
  ++structure_version_;
  return true;
}

RowRef World::move_entity(Entity e, Archetype& to) {
  Slot& s = slots_[e.index];
  Archetype& from = *s.archetype;
  const RowRef old_row = s.row;
  const RowRef new_row = to.push_back(e, tick_);
  const auto from_types = from.types();
  for (std::size_t c = 0; c < from_types.size(); ++c) {
    const int dst_col = to.column_of(from_types[c]);
    void* src = from.slot(old_row, static_cast<int>(c));
    if (dst_col >= 0) {
      type_info(from_types[c]).relocate(to.slot(new_row, dst_col), src);
    } else {
      type_info(from_types[c]).destroy(src);
    }
  }
  const Entity moved = from.swap_remove(old_row, /*destroy_components=*/false, tick_);
  if (!moved.is_null()) slots_[moved.index].row = old_row;
  s.archetype = &to;
  s.row = new_row;
  ++structure_version_;
  return new_row;
}

void* World::add_erased(Entity e, TypeId type, void* value) {
  if (live_slot(e) == nullptr) {
    throw std::invalid_argument("penumbra::ecs::World::add<" + std::string(type_info(type).name) +
                                ">: entity " + std::to_string(e.index) + ":" +
                                std::to_string(e.generation) + " is not alive");
  }
  Slot& s = slots_[e.index];
  const int existing = s.archetype->column_of(type);
  if (existing >= 0) {  // replace in place
    void* dst = s.archetype->slot(s.row, existing);
    type_info(type).destroy(dst);
    type_info(type).move_construct(dst, value);
    s.archetype->mark_changed(s.row.chunk, existing, tick_);
    return dst;
  }
  Archetype& to = neighbour(*s.archetype, type, /*adding=*/true);
  const RowRef row = move_entity(e, to);
  void* dst = to.slot(row, to.column_of(type));
  type_info(type).move_construct(dst, value);
  return dst;
}

bool World::remove_erased(Entity e, TypeId type) {
  const Slot* s = live_slot(e);
  if (s == nullptr || s->archetype->column_of(type) < 0) return false;
  move_entity(e, neighbour(*s->archetype, type, /*adding=*/false));
  return true;
}

void* World::get_erased(Entity e, TypeId type) const {
  const Slot* s = live_slot(e);
  if (s == nullptr) return nullptr;
  const int col = s->archetype->column_of(type);
  return col < 0 ? nullptr : s->archetype->slot(s->row, col);
}

void* World::get_mut_erased(Entity e, TypeId type) {
  const Slot* s = live_slot(e);
  if (s == nullptr) return nullptr;
  const int col = s->archetype->column_of(type);
  if (col < 0) return nullptr;
  s->archetype->mark_changed(s->row.chunk, col, tick_);
  return s->archetype->slot(s->row, col);
}

void World::missing_resource(std::string_view name) {
  throw std::out_of_range("penumbra::ecs::World: no resource of type " + std::string(name));
}

}  // namespace penumbra::ecs
