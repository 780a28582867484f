// The environment group's key-light cases (issue 15, "Accuracy and benchmarks"): the terrain shaded
// from the map's SH alone (n = 0) and with its sources as key lights (n = 1..found), each timed
// (the compose of one frame: shade_environment, and per key light its horizon sweep and shading,
// TerrainShadowing::key_light_horizons / add_key_light) and compared with the reference integrator
// (tests/terrain_shadow terrain_reference.h: the dem crop and mountains at 256^2, 32 x 32 texel
// receivers, 1,024 directions each, the full-resolution map). --records_out writes one JSON record
// per case, --chart_out the chart of error against time (one series per map, labelled with n).
#pragma once

#include <string>

#include "bench_registry.h"

namespace penumbra::bench::environment_keys {

// Registers BM_TerrainKeyLights/<scene>/<map>/n:<n> for the scenes and maps below.
void register_benchmarks();
// Adds its summary rows (ms against the n = 0 case, error) to `s`.
void summarize(const Results& r, Summary& s);
// Writes the records and the chart ("" paths: not written).
void write_outputs(const Results& r, const std::string& records_path,
                   const std::string& chart_path);

}  // namespace penumbra::bench::environment_keys
