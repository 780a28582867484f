// The stability table's registry (issue 17): a failure-mode, bad-input or degenerate-case test
// says what it feeds the system, what happens and what mitigates it, and records the error it
// measures; scripts/stability_table.py collects the records into docs/stability.md and the
// benchmark report. The table is generated from these calls, never typed.
//
//   TEST(SphereBlocker, DegenerateSpheresAreFinite) {
//     PENUMBRA_STABILITY("a sphere of radius 0 / containing the receiver", "finite: no
//                        occlusion / full occlusion", "radius clamped, receiver inside -> 1");
//     ...
//     PENUMBRA_STABILITY_MEASURE("max |visibility - 1|", err);
//
// Put PENUMBRA_STABILITY first in the test body, before any early return or GTEST_SKIP, so the
// case is recorded whenever the test runs; several calls in one test are several rows, and a
// measurement belongs to the last one. scripts/stability_table.py --check fails when a call in
// the sources has no record (the table cannot go stale silently).
//
// Record file (one per call, replaced atomically each time it changes):
//   $PENUMBRA_STABILITY_DIR (or the build's tests/stability folder, set by CMake)/
//     <Suite>.<Test>@<line>.json
// line 1: {"format":"penumbra-stability","version":1,"test":...,"file":...,"line":...,
//          "input":...,"behaviour":...,"mitigation":...,"measured":[{"what":...,"value":...}]}
// line 2: "crc32 XXXXXXXX", the CRC-32 (zlib's) of line 1's bytes.
//
// Threading: call from the test's own thread (gtest's main thread).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::test::stability {

struct Case {
  std::string test, file, input, behaviour, mitigation;
  int line = 0;
  std::vector<std::pair<std::string, double>> measured;
  std::string path;  // record file; empty: not recording
};

inline Case& current() {
  static Case c;
  return c;
}

inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

inline std::uint32_t crc32(const std::string& bytes) {  // zlib's CRC-32 (polynomial 0xEDB88320)
  std::uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    c ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

inline std::string record_text(const Case& c) {
  std::string j =
      "{\"format\":\"penumbra-stability\",\"version\":1,\"test\":" + json_string(c.test) +
      ",\"file\":" + json_string(c.file) + ",\"line\":" + std::to_string(c.line) +
      ",\"input\":" + json_string(c.input) + ",\"behaviour\":" + json_string(c.behaviour) +
      ",\"mitigation\":" + json_string(c.mitigation) + ",\"measured\":[";
  for (std::size_t i = 0; i < c.measured.size(); ++i) {
    char value[64];
    const double v = c.measured[i].second;
    if (std::isfinite(v))
      std::snprintf(value, sizeof value, "%.6g", v);
    else
      std::snprintf(value, sizeof value, "null");
    j += (i ? ",{\"what\":" : "{\"what\":") + json_string(c.measured[i].first) +
         ",\"value\":" + value + "}";
  }
  j += "]}";
  char crc[32];
  std::snprintf(crc, sizeof crc, "crc32 %08x", crc32(j));
  return j + "\n" + crc + "\n";
}

// Writes the current case's record (temporary file, then rename); a failure to write is a test
// failure naming the path.
inline void write_current() {
  const Case& c = current();
  if (c.path.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(c.path).parent_path(), ec);
  const std::string tmp = c.path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << record_text(c);
    if (!f) {
      ADD_FAILURE() << "stability record: cannot write " << tmp;
      return;
    }
  }
  std::filesystem::rename(tmp, c.path, ec);
  if (ec) ADD_FAILURE() << "stability record: cannot rename " << tmp << " to " << c.path;
}

inline std::string record_dir() {
  if (const char* env = std::getenv("PENUMBRA_STABILITY_DIR"); env && *env) return env;
#ifdef PENUMBRA_STABILITY_DIR
  return PENUMBRA_STABILITY_DIR;
#else
  return {};
#endif
}

inline void begin_case(const char* file, int line, std::string input, std::string behaviour,
                       std::string mitigation) {
  Case c;
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  c.test = info ? std::string(info->test_suite_name()) + "." + info->name() : "(no test)";
  c.file = file;
  c.line = line;
  c.input = std::move(input);
  c.behaviour = std::move(behaviour);
  c.mitigation = std::move(mitigation);
  const std::string dir = record_dir();
  if (info && !dir.empty()) {
    std::string name = c.test + "@" + std::to_string(line) + ".json";
    for (char& ch : name)
      if (ch == '/' || ch == '\\') ch = '_';  // parameterised tests: Prefix/Suite.Name/0
    c.path = (std::filesystem::path(dir) / name).string();
  }
  current() = std::move(c);
  write_current();
}

inline void measure(std::string what, double value) {
  current().measured.emplace_back(std::move(what), value);
  write_current();
}

}  // namespace penumbra::test::stability

#define PENUMBRA_STABILITY(input, behaviour, mitigation) \
  ::penumbra::test::stability::begin_case(__FILE__, __LINE__, input, behaviour, mitigation)
#define PENUMBRA_STABILITY_MEASURE(what, value) \
  ::penumbra::test::stability::measure(what, static_cast<double>(value))
