// Entity handles: a 32-bit slot index plus a 32-bit generation.
//
// Destroying an entity bumps its slot's generation, so every handle to it goes stale and is
// detected (World::alive). A slot whose generation would wrap is retired, never reused, so a
// stale handle can never alias a newer entity.
#pragma once

#include <cstdint>
#include <functional>

namespace penumbra::ecs {

struct Entity {
  static constexpr std::uint32_t kInvalidIndex = 0xFFFFFFFFu;
  // Generation reserved for placeholders returned by CommandBuffer::create (never live).
  static constexpr std::uint32_t kPendingGeneration = 0xFFFFFFFFu;

  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;

  constexpr bool is_null() const { return index == kInvalidIndex; }
  constexpr bool is_pending() const { return generation == kPendingGeneration; }
  constexpr std::uint64_t bits() const { return (std::uint64_t{generation} << 32) | index; }
  friend constexpr bool operator==(Entity, Entity) = default;
};

inline constexpr Entity kNullEntity{};

}  // namespace penumbra::ecs

template <>
struct std::hash<penumbra::ecs::Entity> {
  std::size_t operator()(penumbra::ecs::Entity e) const noexcept {
    return std::hash<std::uint64_t>{}(e.bits());
  }
};
