// The valley game in the main job (--scene valley, the default): where each step's input comes
// from (a recorded session, the autopilot or the window's devices), recording it, and the end.
// Private to penumbra_play.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/ecs/world.h"
#include "penumbra/game/game_input.h"
#include "penumbra/game/valley_game.h"

struct GLFWwindow;

namespace penumbra::play {

struct Options;

// Headless frames the autopilot may take (a round ends well before: ValleyConfig::time_limit).
inline constexpr int kAutopilotFrameCap = 6000;

// The committed session `./penumbra play` replays headless (recorded by the autopilot).
std::string default_session_path();

class ValleySession {
 public:
  // Replays options.input (headless default: default_session_path()) unless options.autopilot
  // or a window drives it; throws assets::LoadError naming a bad recording.
  ValleySession(ecs::World& world, const Options& options, bool window);

  // Before each step, outside the job graph: this step's input into GameInput (autopilot or
  // window devices; a replay feeds it in game_input) and into the recording.
  void before_step(ecs::World& world, std::uint64_t frame, GLFWwindow* window);
  // Headless: true once the round ended (won or lost) `linger` frames ago.
  bool finished(std::uint64_t frame, int linger = 45) const;
  // Frames the replay holds (0: not replaying).
  std::size_t replay_steps() const { return replay_steps_; }
  // Prints the final line (phase, score, beacons, time) and writes the recording (--record).
  void finish(const ecs::World& world);
  // HUD lines for the window's overlay.
  std::vector<std::string> hud(const ecs::World& world) const;

 private:
  game::GameInput window_input(GLFWwindow* window);

  const Options& options_;
  game::ValleyConfig config_;
  bool autopilot_ = false, window_ = false;
  std::size_t replay_steps_ = 0;
  game::InputRecording recorded_;
  std::uint64_t ended_at_ = 0;
  bool ended_ = false;
  std::uint8_t buttons_down_ = 0;  // window: last frame's buttons, for presses
};

}  // namespace penumbra::play
