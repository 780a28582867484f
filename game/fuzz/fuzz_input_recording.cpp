// libFuzzer target: the valley game's input recording reader (game_input.h). Replayed on the
// committed corpus (corpus/input_recording) and the committed session by ctest in every build
// (tests/game/CMakeLists.txt), with engine/assets/fuzz/replay_main.cpp as its main.
#include <cstddef>
#include <cstdint>

#include "penumbra/assets/load_error.h"
#include "penumbra/game/game_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace penumbra::game;
  try {
    const InputRecording r =
        parse_input_recording({reinterpret_cast<const char*>(data), size}, "fuzz.pinput");
    // What the reader promises: values in range, and what it read encodes and reads back equal.
    if (r.steps.size() > kMaxInputSteps) __builtin_trap();
    for (const GameInput& in : r.steps)
      if (in.move_x < -127 || in.move_y < -127 || in.turn < -127 || in.buttons > 31)
        __builtin_trap();
    if (parse_input_recording(encode_input_recording(r), "fuzz.again") != r) __builtin_trap();
  } catch (const penumbra::assets::LoadError&) {
  }
  return 0;
}
