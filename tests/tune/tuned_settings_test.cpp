// Settings files (engine/settings/tuned_settings.h): round trip, the writer's atomic replace,
// and every rejection the header promises, each naming the file and the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "penumbra/assets/load_error.h"
#include "penumbra/settings/tuned_settings.h"

namespace penumbra::settings {
namespace {

TunedSettings sample() {
  TunedSettings s;
  s.scene = "tune_ridge";
  s.budget = 0.03;
  s.terrain.horizon = "march";
  s.terrain.level_step = 2;
  s.terrain.azimuths = 8;
  s.terrain.bands = 5;
  s.terrain.result = {true, 0.0281, true, 0.97, 0.97, 4, 48};
  s.blockers.spheres_per_object = 64;
  s.blockers.epsilon = 0.3f;
  s.blockers.result = {true, 0.0589, false, 0.6, 0.6, 18, 80};
  s.spherical_lights.gather = "clusters_leaves";
  s.probes.spacing = 23.6f;
  s.probes.probes_per_side = 11;
  s.probes.placement = "spawn_merge";
  s.probes.result = {true, 0.0443, true, 654, 352.7, 8, 14};
  return s;
}

// The message of parse_settings on `bytes`, "" when it parses.
std::string rejection(const std::string& bytes) {
  try {
    parse_settings(bytes, "x.settings");
  } catch (const assets::LoadError& e) {
    EXPECT_EQ(e.file(), "x.settings");
    return e.reason();
  }
  return "";
}

// The file with its payload replaced (header recomputed: length and checksum match).
std::string with_payload(const std::string& file, const std::string& from, const std::string& to) {
  const std::size_t eol = file.find('\n');
  std::string payload = file.substr(eol + 1);
  const std::size_t at = payload.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  payload.replace(at, from.size(), to);
  // Re-sign through a round trip of the header format.
  char h[96];
  std::uint64_t x = 0xcbf29ce484222325ull;
  for (unsigned char c : payload) x = (x ^ c) * 0x100000001b3ull;
  std::snprintf(h, sizeof h, "penumbra-settings 1 %zu %016llx\n", payload.size(),
                static_cast<unsigned long long>(x));
  return h + payload;
}

TEST(TunedSettings, RoundTrip) {
  const TunedSettings s = sample();
  const std::string bytes = encode_settings(s);
  EXPECT_EQ(bytes.rfind("penumbra-settings 1 ", 0), 0u);
  EXPECT_EQ(parse_settings(bytes, "x"), s);
  EXPECT_EQ(rejection(with_payload(bytes, "\"march\"", "\"march\"")), "");  // re-signing works
}

TEST(TunedSettings, SaveIsAtomicAndLoads) {
  const auto dir = std::filesystem::temp_directory_path() / "penumbra_tuned_settings_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "a.settings";
  save_settings(file, sample());
  TunedSettings t = sample();
  t.terrain.azimuths = 16;
  save_settings(file, t);  // replaces
  EXPECT_EQ(load_settings(file), t);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "a.settings") << "a temporary file was left behind";
  std::filesystem::remove_all(dir);
}

TEST(TunedSettings, MissingFileNamesIt) {
  try {
    load_settings("/nonexistent/dir/x.settings");
    FAIL();
  } catch (const assets::LoadError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/dir/x.settings");
    EXPECT_EQ(e.reason(), "no such file");
  }
}

TEST(TunedSettings, RejectsCorruptInput) {
  const std::string good = encode_settings(sample());
  EXPECT_EQ(rejection(""), "empty file");
  EXPECT_NE(rejection("{\"scene\": 1}").find("no header line"), std::string::npos);
  EXPECT_NE(rejection("penumbra-settingz 1 2 0000000000000000\n{}").find("not a penumbra settings"),
            std::string::npos);
  std::string v2 = good;
  v2[std::string("penumbra-settings ").size()] = '2';
  EXPECT_NE(rejection(v2).find("unsupported version 2"), std::string::npos);
  EXPECT_NE(rejection(good.substr(0, good.size() - 10)).find("truncated"), std::string::npos);
  EXPECT_NE(rejection(good + "x").find("1 trailing bytes"), std::string::npos);
  std::string flipped = good;
  flipped[good.size() - 5] ^= 1;
  EXPECT_NE(rejection(flipped).find("checksum mismatch"), std::string::npos);
  EXPECT_NE(rejection("penumbra-settings 1 2 zz\n{}").find("bad checksum field"),
            std::string::npos);
  EXPECT_NE(rejection("penumbra-settings 1 -2 0000000000000000\n{}").find("bad payload length"),
            std::string::npos);
}

TEST(TunedSettings, RejectsBadFields) {
  const std::string good = encode_settings(sample());
  EXPECT_NE(rejection(with_payload(good, "\"march\"", "\"spiral\""))
                .find("terrain.horizon: unknown value"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"azimuths\": 8", "\"azimuths\": 2"))
                .find("terrain.azimuths: out of range"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"azimuths\": 8", "\"azimuths\": 8.5"))
                .find("expected an integer"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"bands\": 5", "\"bandz\": 5")).find("unknown field"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"scene\": \"tune_ridge\",", "")).find("scene: missing"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"budget\": 0.03", "\"budget\": 0"))
                .find("budget: out of range"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"budget\": 0.03", "\"budget\": \"0.03\""))
                .find("expected a number"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"budget\": 0.03,", "")).find("budget: missing"),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "{", "[")).find("not JSON"), std::string::npos);
}

// spherical_lights.gather is optional (files from before the knob load as "receivers"), written
// always, and checked like the other enums.
TEST(TunedSettings, GatherIsOptionalAndChecked) {
  const std::string good = encode_settings(sample());
  EXPECT_NE(good.find("\"gather\": \"clusters_leaves\""), std::string::npos);
  const TunedSettings old = parse_settings(
      with_payload(good, "\"gather\": \"clusters_leaves\",\n    ", ""), "old.settings");
  EXPECT_EQ(old.spherical_lights.gather, "receivers");
  TunedSettings expected = sample();
  expected.spherical_lights.gather = "receivers";
  EXPECT_EQ(old, expected);
  EXPECT_EQ(parse_settings(with_payload(good, "\"clusters_leaves\"", "\"clusters_parents\""), "x")
                .spherical_lights.gather,
            "clusters_parents");
  EXPECT_NE(rejection(with_payload(good, "\"clusters_leaves\"", "\"clusters\""))
                .find("spherical_lights.gather: unknown value \"clusters\""),
            std::string::npos);
  EXPECT_NE(rejection(with_payload(good, "\"clusters_leaves\"", "3")).find("expected a string"),
            std::string::npos);
  TunedSettings s = sample();
  s.spherical_lights.gather = "all";
  EXPECT_THROW(encode_settings(s), std::invalid_argument);
}

TEST(TunedSettings, WriterRejectsWhatTheReaderWould) {
  TunedSettings s = sample();
  s.terrain.bands = 9;
  EXPECT_THROW(encode_settings(s), std::invalid_argument);
  s = sample();
  s.probes.placement = "random";
  EXPECT_THROW(encode_settings(s), std::invalid_argument);
  s = sample();
  s.budget = std::nan("");
  EXPECT_THROW(encode_settings(s), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::settings
