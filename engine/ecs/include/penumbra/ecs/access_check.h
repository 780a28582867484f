// Declared-access checks: in builds with assertions (NDEBUG not defined), a running system that
// touches a component or resource it did not declare throws AccessViolation, naming the system,
// the type and the missing declaration. Release builds compile the checks out.
//
// The job graph's Executor installs the running system's declaration on its thread with an
// AccessScope; World::get / get_mut / has / resource / try_resource, the Query constructor and
// the structural calls check against it. With no scope installed (set-up code, the main loop,
// tests, sync points applying commands) nothing is checked.
//
// Rules inside a system:
//  - reading T (`const T` in a query, get<T>, has<T>, resource<const T>) needs T in reads or
//    writes;
//  - writing T (`T` in a query, get_mut<T>, resource<T>) needs T in writes;
//  - create, destroy, add, remove and emplace_resource throw: systems record commands instead.
//
// Threading: the scope is per thread. The Executor runs each system inside
// tbb::this_task_arena::isolate when checks are on, so a thread waiting inside one system's
// parallel_for only helps with that system's work and never runs another system's code under
// the wrong scope. Worker threads helping a parallel_for run with no scope (unchecked).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "penumbra/ecs/type_info.h"

namespace penumbra::ecs {

#ifdef NDEBUG
inline constexpr bool kAccessChecks = false;
#else
inline constexpr bool kAccessChecks = true;
#endif

// What the running system declared (jobs::Access, seen from the ECS).
struct DeclaredAccess {
  std::string_view system;
  const TypeSet* reads = nullptr;
  const TypeSet* writes = nullptr;
};

class AccessViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// The declaration installed on this thread; nullptr when none.
const DeclaredAccess* current_access() noexcept;

// Installs `access` on this thread for the scope's lifetime (restores the previous one).
class AccessScope {
 public:
  explicit AccessScope(const DeclaredAccess* access) noexcept;
  ~AccessScope();
  AccessScope(const AccessScope&) = delete;
  AccessScope& operator=(const AccessScope&) = delete;

 private:
  const DeclaredAccess* previous_;
};

namespace detail {
[[noreturn]] void access_violation(const DeclaredAccess& a, TypeId type, std::string_view what);
void check_access(TypeId type, bool write);
void check_structural(std::string_view what);
}  // namespace detail

// Checks a read (or write) of T against the running system's declaration.
template <class T>
void check_read() {
  if constexpr (kAccessChecks) detail::check_access(type_id<T>(), false);
}
template <class T>
void check_write() {
  if constexpr (kAccessChecks) detail::check_access(type_id<T>(), true);
}
// `const T` reads, `T` writes.
template <class T>
void check_use() {
  if constexpr (std::is_const_v<T>) {
    check_read<T>();
  } else {
    check_write<T>();
  }
}
inline void check_structural(std::string_view what) {
  if constexpr (kAccessChecks) detail::check_structural(what);
}

}  // namespace penumbra::ecs
