// Resource: the scene's current probe cloud (data/probe_cloud.h), shared and immutable.
// A scene that loads another cloud calls replace(): the new pointer and a bumped generation make
// probes.prepare rebuild its walk, and every cached cell (ProbeAnchor) of the old cloud is then
// ignored (a fallback locate); assigning `cloud` directly does the same, since probes.prepare
// compares pointers too. The walk holds its own reference, so a replaced cloud lives on until
// the next frame's probes.prepare. Null: no cloud, probes.walk leaves every entity as it is.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>

#include "penumbra/data/probe_cloud.h"

namespace penumbra::components {

struct ProbeCloudResource {
  std::shared_ptr<const data::ProbeCloud> cloud;
  std::uint64_t generation = 0;  // bumped by replace()

  void replace(std::shared_ptr<const data::ProbeCloud> next) {
    cloud = std::move(next);
    ++generation;
  }
};

}  // namespace penumbra::components
