// Tune scenes (game/tune/tune_scene.h): the committed scenes load, objects rest on the terrain,
// the bake scene made from one parses, and bad input is an error naming the file and field.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>

#include "penumbra/systems/probe_bake/bake_scene.h"
#include "tune/tune_scene.h"

namespace penumbra::tune {
namespace {

const std::filesystem::path kRoot = PENUMBRA_SOURCE_DIR;
const std::filesystem::path kData = PENUMBRA_SHARED_DATA;

TEST(TuneScene, CommittedScenesLoad) {
  for (const char* name : {"tune_ridge", "tune_valley", "tune_hills"}) {
    const TuneScene s = load_tune_scene(kRoot / "scenes" / (std::string(name) + ".json"), kData);
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.field->width, 64);
    EXPECT_FALSE(s.objects.empty());
    for (const TuneObject& o : s.objects) {
      float lo = std::numeric_limits<float>::max();
      for (const glm::vec3& v : o.mesh.positions) lo = std::min(lo, v.z);
      EXPECT_NEAR(lo, o.ground.z, 1.5f) << o.model;  // resting just above the ground
      EXPECT_GT(lo, o.ground.z - 1e-3f) << o.model;
      EXPECT_GT(o.radius, 0);
    }
    // The probe bake reads the scene as one of its own.
    const probe_bake::BakeScene bake =
        probe_bake::parse_bake_scene(bake_scene_json(s, 20), s.source, kData);
    EXPECT_EQ(bake.desc.height_fields.size(), 1u);
    EXPECT_EQ(bake.desc.meshes.size(), s.objects.size());
  }
}

std::string error_of(const std::string& json) {
  try {
    parse_tune_scene(json, "bad.json", kData);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(TuneScene, BadInputNamesFileAndField) {
  const std::string terrain =
      R"("terrain": {"file": "terrain/jacksboro_fault_dem.pgm", "crop": [0, 0, 16, 16],
          "cell_size": 4, "height_scale": 0.1, "albedo": [0.3, 0.3, 0.3], "stride": 4})";
  const std::string env = R"("environment": {"file": "hdri/city.exr", "rotation_deg": 0})";
  const std::string probes = R"("probes": {"min": [0, 0, 0], "max": [60, 60, 40], "points": 8})";
  const std::string ok =
      "{\"name\": \"t\", " + terrain + ", " + env + ", \"objects\": [], " + probes + "}";
  EXPECT_EQ(error_of(ok), "");
  EXPECT_NE(error_of("{\"nme\": 1}").find("bad.json: scene.nme: unknown field"), std::string::npos);
  std::string bad = ok;
  bad.replace(bad.find("\"stride\": 4"), 11, "\"stride\": 0");
  EXPECT_NE(error_of(bad).find("bad.json: terrain.stride: out of range"), std::string::npos);
  bad = ok;
  bad.replace(bad.find("[60, 60, 40]"), 12, "[0, 60, 40]");
  EXPECT_NE(error_of(bad).find("max must exceed min"), std::string::npos);
  EXPECT_NE(error_of("not json").find("bad.json: not JSON"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::tune
