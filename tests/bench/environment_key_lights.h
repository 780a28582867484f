// The environment group's key-light cases (issue 15, "Accuracy and benchmarks"): a scene shaded
// from the map's SH alone (n = 0) and with its first n sources as key lights (n = 1..found, up to
// 3), each timed and compared with the reference integrator (errors as terrain_reference.h's
// compare: RGB norm, relative RMS and max, the reference's own noise):
//  - terrains (the dem crop and mountains at 256^2): the compose of one frame (shade_environment,
//    and per key light its horizon sweep and shading, TerrainShadowing::key_light_horizons /
//    add_key_light) against tests/terrain_shadow terrain_reference.h (32 x 32 texel receivers,
//    1,024 directions each, the full-resolution map);
//  - "sphere": one sphere blocker over a plane (BlockerAccumulation: SH visibility of the OEM,
//    key_light_visibility per source), 17 x 17 receivers, 4,096 reference directions each.
// Maps: sky, sunset, sunrise, studio (../shared/data/hdri) and studio_sun, studio.exr plus a sun
// built in code (tests/environment/three_source_map.h), the one with three sources.
// --records_out writes one JSON record per case, --chart_out the chart of error against time
// (one series per map, each point labelled with its scene and n), --chart_n_out the chart of
// error against n (one line per scene and map: colour the map, dash the scene).
#pragma once

#include <string>

#include "bench_registry.h"

namespace penumbra::bench::environment_keys {

// Registers BM_TerrainKeyLights/<terrain>/<map>/n:<n> and BM_BlockerKeyLights/<map>/n:<n>.
void register_benchmarks();
// Adds its summary rows (ms against the n = 0 case, error) to `s`.
void summarize(const Results& r, Summary& s);
// Writes the records, the chart of error against time and the chart of error against n ("" paths:
// not written).
void write_outputs(const Results& r, const std::string& records_path, const std::string& chart_path,
                   const std::string& chart_n_path);

}  // namespace penumbra::bench::environment_keys
