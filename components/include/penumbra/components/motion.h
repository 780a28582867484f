// Motion components: plain data integrated by the motion systems of the sample world and the
// demo. Units: metres and seconds.
#pragma once

namespace penumbra::components {

struct Position {
  float x = 0, y = 0, z = 0;
};

struct Velocity {
  float x = 0, y = 0, z = 0;
};

// Seconds left before the entity is destroyed.
struct Lifetime {
  float seconds = 0;
};

}  // namespace penumbra::components
