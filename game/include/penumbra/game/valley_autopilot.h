// A scripted player for the valley game: from the round's state it makes the input a person
// would (start, steer the orb to the nearest dark beacon, turn the camera after it, one dig and
// one pause along the way to show them). It is what records the committed session that
// `./penumbra play` replays headless (game/sessions/, docs/game.md), and the tests' opponent.
// Threading: a pure function of its arguments.
#pragma once

#include <cstdint>
#include <span>

#include "penumbra/game/game_input.h"
#include "penumbra/game/valley_game.h"

namespace penumbra::game {

struct AutopilotView {
  const GameState* state = nullptr;
  const Orb* orb = nullptr;
  std::span<const Beacon> beacons;
  std::uint64_t frame = 0;  // frames since the program started (title screen included)
};

GameInput autopilot_input(const AutopilotView& view, const ValleyConfig& config);

}  // namespace penumbra::game
