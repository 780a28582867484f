// Soak: the committed session replayed again and again through every system (no renderer: its
// own soak is tests/render/soak_test.cpp), 1,800 frames by default (a minute of game time; set
// PENUMBRA_SOAK_FRAMES=9000 for the five minutes of issue 16, e.g. under ASan). The live heap
// must stay flat after the first replay: allocated bytes (the sanitizer allocator's under ASan,
// glibc's otherwise, so ASan's quarantine does not count) grow by less than 4 MiB from the end
// of the first replay to the end.
#include <gtest/gtest.h>

#include <malloc.h>

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "penumbra/game/valley_game.h"
#include "penumbra/jobs/executor.h"
#include "valley_replay.h"

// PENUMBRA_ASAN: the top CMakeLists.txt defines it in ASan trees, which do not instrument
// the test files (no __SANITIZE_ADDRESS__ there).
#if defined(__SANITIZE_ADDRESS__) || defined(PENUMBRA_ASAN)
#define PENUMBRA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_ASAN 1
#endif
#endif
#ifdef PENUMBRA_ASAN
// The sanitizer runtime's (declared by hand: GCC ships no sanitizer/allocator_interface.h).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace penumbra::game {
namespace {

std::size_t live_heap_bytes() {
#ifdef PENUMBRA_ASAN
  return __sanitizer_get_current_allocated_bytes();
#else
  return mallinfo2().uordblks;
#endif
}

TEST(ValleySoak, RoundAfterRoundTheHeapStaysFlat) {
  const char* env = std::getenv("PENUMBRA_SOAK_FRAMES");
  const long frames = env ? std::strtol(env, nullptr, 10) : 1800;
  ASSERT_GT(frames, 0) << "PENUMBRA_SOAK_FRAMES must be a positive frame count";
  TerrainDemoConfig demo;
  demo.probes.count = 0;  // the floaters' probe bake is start-up work, not per-frame
  test::ValleyReplay replay(2, demo);
  InputPlayback& playback = replay.playback();
  const std::size_t round = playback.recording.steps.size();
  std::size_t warm = 0;
  int rounds = 0;
  for (long f = 0; f < frames; ++f) {
    replay.step();
    if (playback.next >= round) {  // the recording ran out: it starts again
      playback.next = 0;
      ++rounds;
      // The first replay wins as recorded. Later ones meet the boulders and creatures elsewhere
      // (the world's clock has moved on), so the same input plays on, until night ends that
      // round and the recording's Start begins another.
      if (rounds == 1) {
        EXPECT_EQ(replay.world.resource<const GameState>().phase, GamePhase::kWon);
        warm = live_heap_bytes();
      }
    }
  }
  const std::size_t end = live_heap_bytes();
  std::printf(
      "soak: %ld frames, %d replays, %d rounds started, live heap %.1f MiB after the first "
      "replay, %.1f MiB at the end\n",
      frames, rounds, replay.world.resource<const GameState>().rounds, warm / 1048576.0,
      end / 1048576.0);
  ASSERT_GE(rounds, 1) << "the soak must cover at least one whole replay";
  EXPECT_LT(static_cast<double>(end), static_cast<double>(warm) + 4.0 * 1048576.0);
}

}  // namespace
}  // namespace penumbra::game
