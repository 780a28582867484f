#include "penumbra/ecs/type_info.h"

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>

namespace penumbra::ecs {
namespace {
struct Registry {
  std::mutex mutex;
  std::deque<TypeInfo> infos;  // deque: references stay valid while others register
};
Registry& registry() {
  static Registry r;
  return r;
}
}  // namespace

TypeId detail::register_type(const TypeInfo& info) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  if (r.infos.size() >= kMaxTypes) {
    std::fprintf(stderr,
                 "penumbra::ecs: more than %zu component/resource types (registering %.*s)\n",
                 kMaxTypes, static_cast<int>(info.name.size()), info.name.data());
    std::abort();
  }
  r.infos.push_back(info);
  return static_cast<TypeId>(r.infos.size() - 1);
}

const TypeInfo& type_info(TypeId id) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  return r.infos.at(id);
}

std::size_t registered_type_count() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  return r.infos.size();
}

}  // namespace penumbra::ecs
