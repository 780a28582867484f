// What a system touches: the read and write sets the job graph orders systems by.
#pragma once

#include "penumbra/ecs/type_info.h"

namespace penumbra::jobs {

struct Access {
  ecs::TypeSet reads;   // components and resources read
  ecs::TypeSet writes;  // components and resources written (a write implies a read)
  // Component types the system's deferred commands add or remove.
  ecs::TypeSet structural;
  // The system's commands create or destroy entities (changes what every query sees).
  bool spawns = false;
  // Sync points: exclusive access to the whole world.
  bool exclusive = false;

  bool touches(const ecs::TypeSet& types) const { return ((reads | writes) & types).any(); }
  bool structural_changes() const { return spawns || structural.any(); }

  // Two accesses conflict when one writes what the other reads or writes, or either is
  // exclusive. Readers of the same data never conflict.
  bool conflicts_with(const Access& o) const {
    if (exclusive || o.exclusive) return true;
    return (writes & (o.reads | o.writes)).any() || (o.writes & reads).any();
  }
};

}  // namespace penumbra::jobs
