// Process-wide ids and type-erased operations for component and resource types.
//
// Every type used as a component or resource gets a small dense TypeId on first use
// (type_id<T>()). Ids index the bitsets that describe archetypes and system access sets, so
// components and resources share one id space of kMaxTypes entries.
// Threading: type_id<T>() is safe to call from any thread (registration takes a mutex once per
// type; later calls read a function-local static).
#pragma once

#include <bitset>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string_view>
#include <type_traits>
#include <utility>

namespace penumbra::ecs {

using TypeId = std::uint32_t;
inline constexpr std::size_t kMaxTypes = 256;
using TypeSet = std::bitset<kMaxTypes>;

// How to move and destroy a value of an erased type. Components must be nothrow movable.
struct TypeInfo {
  std::string_view name;
  std::size_t size = 0;
  std::size_t align = 0;
  bool trivially_relocatable = false;
  // Move-constructs *dst from *src; *src stays alive (moved-from) and its owner destroys it.
  void (*move_construct)(void* dst, void* src) = nullptr;
  // Move-constructs *dst from *src, then destroys *src.
  void (*relocate)(void* dst, void* src) = nullptr;
  void (*destroy)(void* ptr) = nullptr;
};

namespace detail {
TypeId register_type(const TypeInfo& info);

// "T" spelled as the compiler prints it, taken from __PRETTY_FUNCTION__.
template <class T>
constexpr std::string_view type_name() {
  std::string_view p = __PRETTY_FUNCTION__;
  const auto start = p.find("T = ") + 4;
  const auto end = p.find_first_of(";]", start);
  return p.substr(start, end - start);
}

template <class T>
TypeInfo make_type_info() {
  static_assert(std::is_nothrow_move_constructible_v<T>, "components must be nothrow movable");
  static_assert(std::is_nothrow_destructible_v<T>);
  TypeInfo info;
  info.name = type_name<T>();
  info.size = sizeof(T);
  info.align = alignof(T);
  info.trivially_relocatable = std::is_trivially_copyable_v<T>;
  info.move_construct = [](void* dst, void* src) {
    ::new (dst) T(std::move(*static_cast<T*>(src)));
  };
  info.relocate = [](void* dst, void* src) {
    T* s = static_cast<T*>(src);
    ::new (dst) T(std::move(*s));
    s->~T();
  };
  info.destroy = [](void* p) { static_cast<T*>(p)->~T(); };
  return info;
}
}  // namespace detail

const TypeInfo& type_info(TypeId id);
std::size_t registered_type_count();

namespace detail {
template <class U>
TypeId canonical_type_id() {
  static const TypeId id = register_type(make_type_info<U>());
  return id;
}
}  // namespace detail

// `T`, `const T` and `T&` share one id.
template <class T>
TypeId type_id() {
  return detail::canonical_type_id<std::remove_cvref_t<T>>();
}

template <class... Ts>
TypeSet type_set() {
  TypeSet s;
  (s.set(type_id<Ts>()), ...);
  return s;
}

}  // namespace penumbra::ecs
