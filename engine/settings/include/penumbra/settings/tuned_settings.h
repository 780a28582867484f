// Tuned settings files (issue 17, `./penumbra tune SCENE --budget B -o FILE`): per lighting
// system the cheapest configuration whose error on a scene stayed within a budget, with the
// error, time and search figures it was chosen by (docs/tune.md). Plain data: no ECS and no
// system headers here; game/tune/apply_settings.h turns it into the systems' own settings
// structs (TerrainShadowConfig, BlockerSettings, ...) and resources.
//
// Format, version 1: a header line, then the payload (UTF-8 JSON, exactly `length` bytes):
//   penumbra-settings <version> <length> <fnv1a64>\n<payload>
// <version> decimal (1), <length> the payload's byte count in decimal, <fnv1a64> the FNV-1a 64
// of the payload (assets::fnv1a64) as 16 lowercase hex digits. Payload object (every field
// required except spherical_lights.gather, unknown fields are errors):
//   {"scene": str, "budget": num,
//    "terrain":          {"horizon": "sweep"|"march", "level_step": 1..16, "azimuths": 3..256,
//                         "bands": 3..6, "result": R},
//    "blockers":         {"spheres_per_object": 1..1024, "epsilon": (0, 1), "bands": 3..6,
//                         "result": R},
//    "spherical_lights": {"directions_frequency": 1..8, "blocking": "per_sphere"|"per_object",
//                         "horizon": "shrink"|"clip",
//                         "gather": "receivers"|"clusters_leaves"|"clusters_parents" (optional,
//                         "receivers" when absent: files written before the knob still load;
//                         the writer always writes it), "result": R},
//    "probes":           {"spacing": > 0, "probes_per_side": 2..1024,
//                         "placement": "grid"|"spawn_merge"|"gradient", "result": R}}
//   R = {"tuned": bool, "error": >= 0, "met": bool, "cost": >= 0, "ms": >= 0,
//        "evaluations": int >= 0, "grid": int >= 0}
// Numbers must be finite.
// Contract: parse_settings rejects, with an assets::LoadError naming the file and the reason,
// a missing or empty file, a bad header (magic, fields), another version, a truncated payload
// or trailing bytes, a checksum mismatch, payload that is not JSON, and any field missing, of
// the wrong type, out of range, or unknown. save_settings checks the same rules
// (std::invalid_argument) and writes atomically: a temporary file in the target's folder,
// renamed over the target, so a reader never sees a partial file.
// Threading: independent calls may run concurrently (not two writers of the same path).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace penumbra::settings {

inline constexpr std::uint32_t kSettingsVersion = 1;
inline constexpr std::string_view kSettingsMagic = "penumbra-settings";
inline constexpr std::size_t kMaxSettingsPayload = 1u << 20;

// How a system's configuration was chosen (docs/tune.md).
struct TuneResult {
  bool tuned = false;   // false: defaults, never searched
  double error = 0;     // relative RMS error of the chosen configuration on the tuning scene
  bool met = false;     // error <= budget (false: the budget was out of reach; the most accurate)
  double cost = 0;      // the counted cost model's value (docs/tune.md)
  double ms = 0;        // measured time of the configuration on the tuning scene
  int evaluations = 0;  // configurations evaluated by the search
  int grid = 0;         // configurations in the full grid
  bool operator==(const TuneResult&) const = default;
};

struct TerrainTuning {
  std::string horizon = "sweep";  // "sweep" | "march" (TerrainShadowConfig::method)
  int level_step = 4;             // the march's pyramid step ([Meier13] eq. 4.4)
  int azimuths = 32;              // n_phi
  int bands = 4;                  // SH bands
  TuneResult result;
  bool operator==(const TerrainTuning&) const = default;
};

struct BlockerTuning {
  int spheres_per_object = 16;
  float epsilon = 0.2f;  // visibility inside a blocker's cap ([Giraud] fig. 7)
  int bands = 4;
  TuneResult result;
  bool operator==(const BlockerTuning&) const = default;
};

struct SphericalLightTuning {
  int directions_frequency = 3;         // geodesic frequency: 10 f^2 + 2 sample directions per SL
  std::string blocking = "per_sphere";  // "per_sphere" | "per_object" (SlBlocking)
  std::string horizon = "clip";         // "shrink" | "clip": EmitterHorizon at ground receivers
  // The hierarchy cut: "receivers" (irradiance per receiver), "clusters_leaves" or
  // "clusters_parents" (shade(clusters), SlHierarchy kLeaves / kParents, [Guerrero08] sec. 7.3).
  std::string gather = "receivers";
  TuneResult result;
  bool operator==(const SphericalLightTuning&) const = default;
};

struct ProbeTuning {
  float spacing = 10;        // metres between grid probes on the tuning scene
  int probes_per_side = 12;  // the scene's extent / spacing + 1: scale-free, for other terrains
  std::string placement = "grid";  // "grid" | "spawn_merge" | "gradient" (PlacementMethod)
  TuneResult result;
  bool operator==(const ProbeTuning&) const = default;
};

struct TunedSettings {
  std::string scene;  // the scene tuned on
  double budget = 0.03;
  TerrainTuning terrain;
  BlockerTuning blockers;
  SphericalLightTuning spherical_lights;
  ProbeTuning probes;
  bool operator==(const TunedSettings&) const = default;
};

// The whole file's bytes (header + payload). Throws std::invalid_argument on values the reader
// would reject.
std::string encode_settings(const TunedSettings& settings);
// Parses a whole file's bytes; `name` is used in messages. Throws assets::LoadError.
TunedSettings parse_settings(std::string_view bytes, const std::string& name);
// Reads and parses `file` (assets::LoadError naming it).
TunedSettings load_settings(const std::filesystem::path& file);
// encode_settings, then an atomic write (temporary file + rename). Throws std::invalid_argument
// for bad values, std::runtime_error naming the file when it cannot be written.
void save_settings(const std::filesystem::path& file, const TunedSettings& settings);

}  // namespace penumbra::settings
