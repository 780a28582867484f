// One fixed simulation step's player input for the valley game (valley_game.h), and its
// recording: a sequence of steps that replays a session exactly.
//
// Values are quantised (axes to 1/127, buttons to bits) when they are made, so a live session
// and its replay feed the rules the very same numbers: that is what makes a recorded session
// reach the same score bit-identically.
//
// Recording file, version 1: a header line, then the payload (ASCII, exactly `length` bytes):
//   penumbra-input <version> <length> <fnv1a64>\n<payload>
// <fnv1a64>: assets::fnv1a64 of the payload, 16 lowercase hex digits. Payload: one line per run
// of identical steps, "<count> <move_x> <move_y> <turn> <buttons>\n": count in [1, 2^24],
// axes integers in [-127, 127], buttons an integer in [0, 31] (GameButton bits). At most
// kMaxInputSteps steps in all.
// Contract: parse_input_recording rejects, with an assets::LoadError naming the file and the
// reason, an empty or missing file, a bad header, another version, a truncated payload or
// trailing bytes, a checksum mismatch and any malformed or out-of-range line.
// save_input_recording writes atomically (a temporary file renamed over the target).
// Threading: plain values and pure functions (not two writers of the same path).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

namespace penumbra::game {

enum GameButton : std::uint8_t {
  kButtonDig = 1,      // held: lower the ground under the orb
  kButtonRaise = 2,    // held: raise it
  kButtonStart = 4,    // pressed: start (title, end screens)
  kButtonPause = 8,    // pressed: pause / resume
  kButtonRestart = 16  // pressed: restart the round
};

// Axes in 1/127 steps: move (x: right, y: forward, relative to the camera's heading) and turn
// (the camera's heading, positive: to the left).
struct GameInput {
  std::int8_t move_x = 0, move_y = 0, turn = 0;
  std::uint8_t buttons = 0;  // GameButton bits

  glm::vec2 move() const { return glm::vec2(move_x, move_y) / 127.0f; }
  float turn_rate() const { return static_cast<float>(turn) / 127.0f; }
  bool held(GameButton b) const { return (buttons & b) != 0; }
  bool operator==(const GameInput&) const = default;
};

// Quantises an analogue value in [-1, 1] (clamped; NaN is 0) to an axis.
std::int8_t quantize_axis(float v);

inline constexpr std::uint32_t kInputVersion = 1;
inline constexpr std::string_view kInputMagic = "penumbra-input";
inline constexpr std::size_t kMaxInputSteps = 1u << 24;

struct InputRecording {
  std::vector<GameInput> steps;  // one per simulation step
  bool operator==(const InputRecording&) const = default;
};

std::string encode_input_recording(const InputRecording& recording);
InputRecording parse_input_recording(std::string_view bytes, const std::string& file);
InputRecording load_input_recording(const std::filesystem::path& file);
void save_input_recording(const InputRecording& recording, const std::filesystem::path& file);

}  // namespace penumbra::game
