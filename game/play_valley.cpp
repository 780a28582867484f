#include "play_valley.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include <GLFW/glfw3.h>

#include "penumbra/game/valley_autopilot.h"
#include "play.h"

namespace penumbra::play {

std::string default_session_path() {
  return std::string(PENUMBRA_SOURCE_DIR) + "/game/sessions/dusk_run.pinput";
}

ValleySession::ValleySession(ecs::World& world, const Options& o, bool window)
    : options_(o), autopilot_(o.autopilot), window_(window && !o.autopilot) {
  if (autopilot_ || (window_ && o.input.empty())) return;
  game::InputPlayback playback;
  playback.recording =
      game::load_input_recording(o.input.empty() ? default_session_path() : o.input);
  replay_steps_ = playback.recording.steps.size();
  if (!o.record.empty()) recorded_ = playback.recording;
  world.emplace_resource<game::InputPlayback>(std::move(playback));
  window_ = false;
}

game::GameInput ValleySession::window_input(GLFWwindow* w) {
  using game::quantize_axis;
  auto key = [&](int k) { return glfwGetKey(w, k) == GLFW_PRESS; };
  float mx = (key(GLFW_KEY_D) ? 1.0f : 0.0f) - (key(GLFW_KEY_A) ? 1.0f : 0.0f);
  float my = (key(GLFW_KEY_W) || key(GLFW_KEY_UP) ? 1.0f : 0.0f) -
             (key(GLFW_KEY_S) || key(GLFW_KEY_DOWN) ? 1.0f : 0.0f);
  float turn = (key(GLFW_KEY_Q) || key(GLFW_KEY_LEFT) ? 1.0f : 0.0f) -
               (key(GLFW_KEY_E) || key(GLFW_KEY_RIGHT) ? 1.0f : 0.0f);
  std::uint8_t buttons = 0;
  if (key(GLFW_KEY_SPACE) || glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
    buttons |= game::kButtonDig;
  if (key(GLFW_KEY_LEFT_SHIFT) || glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS)
    buttons |= game::kButtonRaise;
  if (key(GLFW_KEY_ENTER)) buttons |= game::kButtonStart;
  if (key(GLFW_KEY_P) || key(GLFW_KEY_TAB)) buttons |= game::kButtonPause;
  if (key(GLFW_KEY_R)) buttons |= game::kButtonRestart;
  GLFWgamepadstate pad;
  if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
    auto dead = [](float v) { return std::abs(v) < 0.15f ? 0.0f : v; };
    mx += dead(pad.axes[GLFW_GAMEPAD_AXIS_LEFT_X]);
    my -= dead(pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y]);  // GLFW: down is positive
    turn -= dead(pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X]);
    if (pad.buttons[GLFW_GAMEPAD_BUTTON_A]) buttons |= game::kButtonStart;
    if (pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.5f) buttons |= game::kButtonDig;
    if (pad.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.5f) buttons |= game::kButtonRaise;
    if (pad.buttons[GLFW_GAMEPAD_BUTTON_START]) buttons |= game::kButtonPause;
    if (pad.buttons[GLFW_GAMEPAD_BUTTON_BACK]) buttons |= game::kButtonRestart;
  }
  // Start, pause and restart act on the press; dig and raise while held.
  constexpr std::uint8_t kPresses = game::kButtonStart | game::kButtonPause | game::kButtonRestart;
  const std::uint8_t pressed = buttons & kPresses & ~buttons_down_;
  buttons_down_ = buttons;
  game::GameInput in{quantize_axis(mx), quantize_axis(my), quantize_axis(turn),
                     static_cast<std::uint8_t>((buttons & ~kPresses) | pressed)};
  return in;
}

void ValleySession::before_step(ecs::World& w, std::uint64_t frame, GLFWwindow* window) {
  const game::GameState& g = w.resource<const game::GameState>();
  if (!ended_ && (g.phase == game::GamePhase::kWon || g.phase == game::GamePhase::kLost)) {
    ended_ = true;
    ended_at_ = frame;
  } else if (g.phase == game::GamePhase::kPlaying) {
    ended_ = false;
  }
  if (w.try_resource<const game::InputPlayback>()) return;  // game_input feeds the replay
  game::GameInput in;
  if (autopilot_) {
    std::vector<game::Beacon> beacons;
    w.query<const game::Beacon>().each([&](const game::Beacon& b) { beacons.push_back(b); });
    const game::Orb* orb = nullptr;
    w.query<const game::Orb>().each([&](const game::Orb& o) { orb = &o; });
    in = game::autopilot_input({&g, orb, beacons, frame}, config_);
  } else if (window_ && window) {
    in = window_input(window);
  }
  w.resource<game::GameInput>() = in;
  if (!options_.record.empty()) recorded_.steps.push_back(in);
}

bool ValleySession::finished(std::uint64_t frame, int linger) const {
  return !window_ && ended_ && frame >= ended_at_ + static_cast<std::uint64_t>(linger);
}

void ValleySession::finish(const ecs::World& w) {
  const game::GameState& g = w.resource<const game::GameState>();
  std::printf("game: %s, final score %d, beacons %d of %d, %.1f s left, %llu steps, %d edits\n",
              game::phase_name(g.phase), g.score, g.beacons_lit, g.beacons_total, g.time_left,
              static_cast<unsigned long long>(g.steps), g.edits);
  if (!options_.record.empty()) {
    game::save_input_recording(recorded_, options_.record);
    std::printf("recording: %s (%zu steps)\n", options_.record.c_str(), recorded_.steps.size());
  }
}

std::vector<std::string> ValleySession::hud(const ecs::World& w) const {
  const game::GameState& g = w.resource<const game::GameState>();
  std::vector<std::string> lines;
  char line[160];
  switch (g.phase) {
    case game::GamePhase::kTitle:
      lines.push_back("DUSK VALLEY: light every beacon before night falls");
      lines.push_back(
          "Enter / A: start   WASD / left stick: roll the orb   Q E / right stick: turn");
      lines.push_back("Space / RT: dig   Shift / LT: raise   P / Start: pause   R / Back: restart");
      return lines;
    case game::GamePhase::kWon:
      std::snprintf(line, sizeof line, "Every beacon lit with %.0f s to spare: score %d",
                    g.time_left, g.score);
      lines.push_back(line);
      lines.push_back("Enter / A: play again");
      return lines;
    case game::GamePhase::kLost:
      std::snprintf(line, sizeof line, "Night fell with %d of %d beacons lit: score %d",
                    g.beacons_lit, g.beacons_total, g.score);
      lines.push_back(line);
      lines.push_back("Enter / A: try again");
      return lines;
    case game::GamePhase::kPaused:
    case game::GamePhase::kPlaying:
      break;
  }
  const int secs = static_cast<int>(std::ceil(g.time_left));
  std::snprintf(line, sizeof line, "%sbeacons %d / %d   score %d   dusk %d:%02d   edits %d",
                g.phase == game::GamePhase::kPaused ? "PAUSED   " : "", g.beacons_lit,
                g.beacons_total, g.score, secs / 60, secs % 60, g.edits);
  lines.push_back(line);
  return lines;
}

}  // namespace penumbra::play
