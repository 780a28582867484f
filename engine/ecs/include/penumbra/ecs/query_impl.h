// Template bodies of Query (needs the complete World). Included by query.h; not on its own.
#pragma once

#include "penumbra/ecs/query.h"
#include "penumbra/ecs/world.h"

namespace penumbra::ecs {

template <class... Ts>
Query<Ts...>::Query(World& world) : world_(&world) {
  (check_use<Ts>(), ...);
  required_ = type_set<Ts...>();
  ((std::is_const_v<Ts> ? reads_.set(type_id<Ts>()) : writes_.set(type_id<Ts>())), ...);
}

template <class... Ts>
std::size_t Query<Ts...>::prepare() {
  const auto archetypes = world_->archetypes();
  for (; examined_ < archetypes.size(); ++examined_) {
    Archetype* a = archetypes[examined_];
    if ((a->signature() & required_) != required_ || (a->signature() & exclude_).any()) continue;
    Match m{a, {a->column_of(type_id<Ts>())...}};
    matched_.push_back(m);
  }
  chunks_.clear();
  for (std::uint32_t m = 0; m < matched_.size(); ++m) {
    Archetype* a = matched_[m].archetype;
    for (std::uint32_t c = 0; c < a->chunk_count(); ++c) chunks_.push_back({a, c, m});
  }
  return chunks_.size();
}

template <class... Ts>
typename Query<Ts...>::View Query<Ts...>::chunk(std::size_t i) const {
  return chunk(i, world_->tick());
}

template <class... Ts>
std::size_t Query<Ts...>::entity_count() const {
  std::size_t n = 0;
  for (const Ref& r : chunks_) n += r.archetype->chunk_size(r.chunk);
  return n;
}

template <class... Ts>
template <class F>
void Query<Ts...>::each(F&& f) {
  const std::size_t n = prepare();
  for (std::size_t c = 0; c < n; ++c) {
    const View view = chunk(c);
    const std::uint32_t rows = view.size();
    auto spans = std::make_tuple(view.template get<Ts>()...);
    if constexpr (std::is_invocable_v<F&, Entity, Ts&...>) {
      const auto ents = view.entities();
      for (std::uint32_t r = 0; r < rows; ++r) f(ents[r], std::get<std::span<Ts>>(spans)[r]...);
    } else {
      for (std::uint32_t r = 0; r < rows; ++r) f(std::get<std::span<Ts>>(spans)[r]...);
    }
  }
}

}  // namespace penumbra::ecs
