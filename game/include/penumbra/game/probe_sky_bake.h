// The main job's probe cloud baked by the probe bake's capture (issue 14, "in the main job the
// terrain scene's cloud is baked once at build or first run and cached"): every probe's
// irradiance SH from reference::radiance_sh (engine/reference, Embree: the environment through
// the terrain and one diffuse bounce off the terrain's albedo, [Sukys14] sec. 3.1), once per sky
// step: the demo's sky turns, so the map is baked at `steps` rotations 2 pi k / steps and the
// demo shows the step nearest the sky's rotation (exact at the steps; the same seed at every
// step, so the noise does not flicker between steps).
//
// Cache: with a cache folder, step k goes to DIR/probe_sky_<key>/sky_<k>.pcld, the probe cloud
// file (assets/probe_cloud_file.h: versioned, checksummed, written atomically; the file's
// positions must equal the cloud's), where <key> is the FNV-1a 64 of every input (the field's
// heights as baked, origin, albedo, the map's texels, the probes' positions, steps, samples,
// bounce, seed and kProbeSkyBakeVersion). A later run with the same inputs loads the steps
// instead of tracing; a file that is missing, corrupt, truncated or for other probes is baked
// again and rewritten (its reason in `notes`). Nothing is ever read from a folder whose key
// differs, so a changed input cannot load stale lighting.
//
// Threading: the capture runs tbb::parallel_for in the caller's arena; deterministic for any
// thread count (radiance_sh's per-point streams).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/mesh.h"
#include "penumbra/data/probe_cloud.h"

namespace penumbra::game {

inline constexpr std::uint32_t kProbeSkyBakeVersion = 1;

// A static mesh in the bake (world frame): it occludes the sky and, with the bounce, reflects
// with its albedo (the valley game's canyon arches).
struct BakeMesh {
  std::shared_ptr<const data::MeshData> mesh;
  glm::vec3 albedo{0.5f};
};

struct ProbeSkyBakeInputs {
  const data::HeightField* field = nullptr;  // heights as the terrain system sees them (scaled)
  glm::vec3 origin{0.0f};                    // world position of sample (0, 0) at height 0
  glm::vec3 albedo{0.5f};                    // the terrain's, for the bounce
  const data::EnvironmentMap* map = nullptr;
  int steps = 64;      // sky rotations, 2 pi / steps apart (>= 1)
  int samples = 256;   // capture samples per probe and step (>= 2)
  bool bounce = true;  // one diffuse bounce off the terrain (and the meshes)
  std::uint64_t seed = 1;
  std::vector<BakeMesh> meshes;  // part of the cache key
};

struct ProbeSkySteps {
  std::vector<std::vector<float>> sh;  // per step: the cloud's irradiance SH; empty: not baked
  std::size_t baked = 0, loaded = 0;   // steps traced this call, steps read from the cache
  double seconds = 0;
  std::filesystem::path folder;    // the cache folder used ("": none)
  std::vector<std::string> notes;  // cache files rebaked and why; a folder that cannot be written
};

// The cache key of `in` for the probes at `positions`.
std::uint64_t probe_sky_bake_key(const ProbeSkyBakeInputs& in,
                                 std::span<const glm::vec3> positions);

// Bakes (or loads from `cache_dir`, when not empty) the steps listed in `which` (empty: all) of
// the SH of `cloud`'s probes (3 bands, data/probe_cloud.h layout). `cloud` supplies positions
// and the cells the cache files carry. Throws std::invalid_argument on bad inputs (no field or
// map, steps < 1, samples < 2, a bad step index, a cloud that is not 3 bands).
ProbeSkySteps bake_probe_sky_steps(const ProbeSkyBakeInputs& in, const data::ProbeCloud& cloud,
                                   const std::filesystem::path& cache_dir,
                                   std::span<const int> which = {});

}  // namespace penumbra::game
