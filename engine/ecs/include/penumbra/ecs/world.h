// World: entities, their components (in archetype tables) and resources (singletons).
//
// Contract: structural changes (create, destroy, add, remove) and resource insertion are made
// by one thread while no system runs; systems running in the job graph record them in
// CommandBuffers instead, applied at sync points. Component data may be read and written from
// many threads as the job graph's read/write sets allow.
//
// Inside a running system, the accessors check the system's declared reads and writes in builds
// with assertions (penumbra/ecs/access_check.h).
//
// Ticks: every write access stamps the touched chunk's column with a tick (see archetype.h).
// The job graph gives each system its own tick per frame, increasing along the graph's edges,
// so "changed since my last run" is exact at chunk granularity.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "penumbra/ecs/access_check.h"
#include "penumbra/ecs/archetype.h"
#include "penumbra/ecs/entity.h"
#include "penumbra/ecs/type_info.h"

namespace penumbra::ecs {

template <class... Ts>
class Query;

class World {
 public:
  World();
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // --- Entities -------------------------------------------------------------------------
  Entity create();
  // Creates an entity that already has `components` (one archetype move, no transitions).
  template <class... Ts>
  Entity create_with(Ts... components);
  // Returns false (and does nothing) when `e` is stale or null.
  bool destroy(Entity e);
  bool alive(Entity e) const;
  std::size_t size() const { return live_; }
  // Index slots ever allocated (live + free + retired); for tests and statistics.
  std::size_t slot_count() const { return slots_.size(); }

  // --- Components -------------------------------------------------------------------------
  // Adds `value`, or replaces the existing component. Throws std::invalid_argument if `e` is
  // not alive.
  template <class T>
  T& add(Entity e, T value) {
    check_structural("add");
    return *static_cast<T*>(add_erased(e, type_id<T>(), &value));
  }
  // Returns false when `e` is not alive or has no T.
  template <class T>
  bool remove(Entity e) {
    check_structural("remove");
    return remove_erased(e, type_id<T>());
  }
  template <class T>
  bool has(Entity e) const {
    check_read<T>();
    return get_erased(e, type_id<T>()) != nullptr;
  }
  // nullptr when `e` is not alive or has no T.
  template <class T>
  const T* get(Entity e) const {
    check_read<T>();
    return static_cast<const T*>(get_erased(e, type_id<T>()));
  }
  // As get(), and marks T in e's chunk changed at tick().
  template <class T>
  T* get_mut(Entity e) {
    check_write<T>();
    return static_cast<T*>(get_mut_erased(e, type_id<T>()));
  }

  // Type-erased forms used by CommandBuffer. add_erased and create_erased move-construct from
  // the values; their owner still destroys the moved-from values.
  void* add_erased(Entity e, TypeId type, void* value);
  bool remove_erased(Entity e, TypeId type);
  void* get_erased(Entity e, TypeId type) const;
  void* get_mut_erased(Entity e, TypeId type);
  Entity create_erased(std::span<const TypeId> types, std::span<void* const> values);

  // --- Resources ----------------------------------------------------------------------------
  // `resource<const T>()` reads, `resource<T>()` writes (what the access checks expect).
  template <class T, class... Args>
  T& emplace_resource(Args&&... args) {
    check_structural("emplace_resource");
    auto ptr = std::make_shared<T>(std::forward<Args>(args)...);
    T& ref = *ptr;
    resources_[type_id<T>()] = std::move(ptr);
    return ref;
  }
  template <class T>
  T* try_resource() const {
    check_use<T>();
    return static_cast<std::remove_const_t<T>*>(resources_[type_id<T>()].get());
  }
  // Throws std::out_of_range naming T when the resource is absent.
  template <class T>
  T& resource() const {
    T* r = try_resource<T>();
    if (r == nullptr) missing_resource(type_info(type_id<T>()).name);
    return *r;
  }
  template <class T>
  bool remove_resource() {
    check_structural("remove_resource");
    auto& slot = resources_[type_id<T>()];
    const bool had = slot != nullptr;
    slot.reset();
    return had;
  }

  // --- Ticks and storage (for queries and the job graph) --------------------------------
  std::uint64_t tick() const { return tick_; }
  void set_tick(std::uint64_t t) { tick_ = t; }
  std::span<Archetype* const> archetypes() const { return archetype_list_; }
  // Counts structural changes; lets caches know when entity locations may have moved.
  std::uint64_t structure_version() const { return structure_version_; }

  template <class... Ts>
  Query<Ts...> query();

 private:
  struct Slot {
    std::uint32_t generation = 0;
    Archetype* archetype = nullptr;  // nullptr: free or retired
    RowRef row;
  };

  Archetype& archetype_for(const TypeSet& signature);
  Archetype& neighbour(Archetype& from, TypeId type, bool adding);
  Entity allocate_entity();
  // Moves entity e from its archetype to `to`; returns the new row. Components present in both
  // are relocated; components only in the old archetype are destroyed.
  RowRef move_entity(Entity e, Archetype& to);
  const Slot* live_slot(Entity e) const;
  [[noreturn]] static void missing_resource(std::string_view name);

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_;  // LIFO: deterministic reuse order
  std::size_t live_ = 0;
  std::vector<std::unique_ptr<Archetype>> archetype_storage_;
  std::vector<Archetype*> archetype_list_;
  std::unordered_map<TypeSet, Archetype*> by_signature_;
  Archetype* empty_ = nullptr;
  std::vector<std::shared_ptr<void>> resources_;  // indexed by TypeId
  std::uint64_t tick_ = 1;
  std::uint64_t structure_version_ = 0;
};

template <class... Ts>
Entity World::create_with(Ts... components) {
  if constexpr (sizeof...(Ts) == 0) return create();
  const TypeId ids[] = {type_id<Ts>()...};
  void* const values[] = {static_cast<void*>(&components)...};
  return create_erased(ids, values);
}

}  // namespace penumbra::ecs

#include "penumbra/ecs/query.h"

namespace penumbra::ecs {
template <class... Ts>
Query<Ts...> World::query() {
  return Query<Ts...>(*this);
}
}  // namespace penumbra::ecs
