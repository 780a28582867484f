#include "penumbra/ecs/access_check.h"

namespace penumbra::ecs {
namespace {
thread_local const DeclaredAccess* t_current = nullptr;
}  // namespace

const DeclaredAccess* current_access() noexcept {
  return t_current;
}

AccessScope::AccessScope(const DeclaredAccess* access) noexcept : previous_(t_current) {
  t_current = access;
}

AccessScope::~AccessScope() {
  t_current = previous_;
}

namespace detail {

void access_violation(const DeclaredAccess& a, TypeId type, std::string_view what) {
  throw AccessViolation("system '" + std::string(a.system) + "' " + std::string(what) + " " +
                        std::string(type_info(type).name));
}

void check_access(TypeId type, bool write) {
  const DeclaredAccess* a = t_current;
  if (a == nullptr) return;
  const bool written = a->writes != nullptr && a->writes->test(type);
  if (write) {
    if (!written) access_violation(*a, type, "writes without declaring writes<>() of");
  } else if (!written && !(a->reads != nullptr && a->reads->test(type))) {
    access_violation(*a, type, "reads without declaring reads<>() of");
  }
}

void check_structural(std::string_view what) {
  const DeclaredAccess* a = t_current;
  if (a == nullptr) return;
  throw AccessViolation("system '" + std::string(a->system) + "' calls World::" +
                        std::string(what) + " while the job graph runs (record a command instead)");
}

}  // namespace detail
}  // namespace penumbra::ecs
