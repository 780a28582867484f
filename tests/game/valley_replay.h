// Test helper: the valley game's world as penumbra_play builds it (every lighting system, no
// renderer), replaying the committed session (game/sessions/dusk_run.pinput).
#pragma once

#include <string>

#include "penumbra/game/valley_game.h"
#include "penumbra/jobs/executor.h"

namespace penumbra::game::test {

struct ValleyReplay {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor;

  // `demo` is the terrain demo's config before valley_world() (cache folders, probe count).
  explicit ValleyReplay(int threads, TerrainDemoConfig demo = {}) : executor(threads) {
    demo = valley_world(demo);
    populate_terrain_demo(world, demo);
    populate_valley(world);
    world.emplace_resource<InputPlayback>(InputPlayback{
        load_input_recording(PENUMBRA_SOURCE_DIR "/game/sessions/dusk_run.pinput"), 0});
    add_terrain_demo_systems(schedule, demo);
  }
  InputPlayback& playback() { return world.resource<InputPlayback>(); }
  std::size_t steps() { return playback().recording.steps.size(); }
  void step() { executor.run(schedule, world); }
};

}  // namespace penumbra::game::test
