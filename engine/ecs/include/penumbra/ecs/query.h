// Queries: the chunks of every archetype that has all of Ts and none of an exclude set.
//
// Ts names the components and the access: `T` is written, `const T` is only read. A query is
// cheap to keep: it caches the archetypes it matched and only examines archetypes created since.
//
//   auto q = world.query<Position, const Velocity>().without<Frozen>();
//   q.each([](Position& p, const Velocity& v) { p.x += v.x; });
//   for (std::size_t c = 0; c < q.prepare(); ++c) { auto chunk = q.chunk(c, tick); ... }
//
// Threading: prepare() must not run concurrently with structural changes. After prepare(),
// chunk(i) may be called from many threads for different i.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "penumbra/ecs/archetype.h"
#include "penumbra/ecs/type_info.h"

namespace penumbra::ecs {

class World;

namespace detail {
template <class U, class... Ts>
constexpr std::size_t index_of() {
  constexpr bool match[] = {std::is_same_v<std::remove_const_t<U>, std::remove_const_t<Ts>>...};
  for (std::size_t i = 0; i < sizeof...(Ts); ++i) {
    if (match[i]) return i;
  }
  return sizeof...(Ts);
}
}  // namespace detail

// One chunk of a query: spans over its rows, one per component of Ts.
template <class... Ts>
class ChunkView {
 public:
  ChunkView(Archetype* archetype, std::uint32_t chunk, const int* columns, std::size_t ordinal,
            std::uint64_t write_tick)
      : archetype_(archetype), chunk_(chunk), ordinal_(ordinal), write_tick_(write_tick) {
    for (std::size_t i = 0; i < sizeof...(Ts); ++i) columns_[i] = columns[i];
  }

  std::uint32_t size() const { return archetype_->chunk_size(chunk_); }
  // Position of this chunk in the query's chunk list (stable order: use it to key per-chunk
  // partial results so reductions do not depend on thread scheduling).
  std::size_t ordinal() const { return ordinal_; }
  std::span<const Entity> entities() const { return {archetype_->entities(chunk_), size()}; }

  // The rows of component U. U must be one of Ts, const-qualified if Ts has it as const.
  // Asking for a mutable U marks U in this chunk as changed.
  template <class U>
  std::span<U> get() const {
    constexpr std::size_t i = detail::index_of<U, Ts...>();
    static_assert(i < sizeof...(Ts), "component not in this query");
    using Declared = std::tuple_element_t<i, std::tuple<Ts...>>;
    static_assert(std::is_const_v<U> || !std::is_const_v<Declared>,
                  "component is declared read-only (const) in this query");
    if constexpr (!std::is_const_v<U>) archetype_->mark_changed(chunk_, columns_[i], write_tick_);
    return {static_cast<U*>(archetype_->column(chunk_, columns_[i])), size()};
  }
  // True when U in this chunk was written after `tick` (chunk granularity, conservative).
  template <class U>
  bool changed_since(std::uint64_t tick) const {
    constexpr std::size_t i = detail::index_of<U, Ts...>();
    static_assert(i < sizeof...(Ts), "component not in this query");
    return archetype_->changed_tick(chunk_, columns_[i]) > tick;
  }

 private:
  Archetype* archetype_;
  std::uint32_t chunk_;
  int columns_[sizeof...(Ts) > 0 ? sizeof...(Ts) : 1] = {};
  std::size_t ordinal_;
  std::uint64_t write_tick_;
};

template <class... Ts>
class Query {
 public:
  static_assert(sizeof...(Ts) > 0, "a query names at least one component");
  using View = ChunkView<Ts...>;

  explicit Query(World& world);

  template <class... Ex>
  Query& without() {
    (exclude_.set(type_id<Ex>()), ...);
    reset_cache();
    return *this;
  }
  Query& without(const TypeSet& exclude) {
    exclude_ |= exclude;
    reset_cache();
    return *this;
  }

  // Refreshes the chunk list; returns the number of non-empty chunks.
  std::size_t prepare();
  std::size_t chunk_count() const { return chunks_.size(); }
  // Chunk `i` of the last prepare(); mutable access is stamped with `write_tick`.
  View chunk(std::size_t i, std::uint64_t write_tick) const {
    const Ref& r = chunks_[i];
    return View(r.archetype, r.chunk, matched_[r.match].columns, i, write_tick);
  }
  View chunk(std::size_t i) const;  // stamped with World::tick()

  // Calls f(Ts&...) or f(Entity, Ts&...) for every matching entity, in chunk order.
  template <class F>
  void each(F&& f);
  // Number of matching entities (after prepare()).
  std::size_t entity_count() const;

  TypeSet reads() const { return reads_; }
  TypeSet writes() const { return writes_; }
  const TypeSet& excluded() const { return exclude_; }

 private:
  struct Match {
    Archetype* archetype;
    int columns[sizeof...(Ts)];
  };
  struct Ref {
    Archetype* archetype;
    std::uint32_t chunk;
    std::uint32_t match;
  };
  void reset_cache() {
    matched_.clear();
    examined_ = 0;
  }

  World* world_;
  TypeSet required_, exclude_, reads_, writes_;
  std::vector<Match> matched_;
  std::size_t examined_ = 0;  // archetypes already tested against required_/exclude_
  std::vector<Ref> chunks_;
};

}  // namespace penumbra::ecs

#include "penumbra/ecs/query_impl.h"
