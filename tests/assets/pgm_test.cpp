#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "common/stability.h"
#include "penumbra/assets/heightmap.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;
using test::TempDir;

std::string pgm16(int w, int h, const std::vector<unsigned>& samples,
                  const std::string& header_extra = "") {
  std::string s = "P5\n" + header_extra + std::to_string(w) + " " + std::to_string(h) + "\n65535\n";
  for (unsigned v : samples) {
    s.push_back(static_cast<char>(v >> 8));
    s.push_back(static_cast<char>(v & 0xFF));
  }
  return s;
}

PgmImage parse(const std::string& s) {
  return parse_pgm({reinterpret_cast<const unsigned char*>(s.data()), s.size()}, "mem.pgm");
}

TEST(Pgm, SharedDemLoadsWithSidecar) {
  const auto path = test::shared_data() / "terrain" / "jacksboro_fault_dem.pgm";
  const auto t0 = std::chrono::steady_clock::now();
  const data::HeightField f = load_height_field(path);
  std::printf(
      "  DEM loaded in %.2f ms\n",
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  // 403x344 samples at 74.4 x 92.6 m: y resampled to 74.4 m spacing, floor(343 * 92.6 / 74.4) + 1.
  EXPECT_EQ(f.width, 403);
  EXPECT_EQ(f.height, 427);
  EXPECT_FLOAT_EQ(f.cell_size, 74.4f);
  // First samples of the file are 0x00f7, 0x00fb: elevation = 236 m + value.
  EXPECT_FLOAT_EQ(f.at(0, 0), 236.0f + 0xf7);
  EXPECT_FLOAT_EQ(f.at(1, 0), 236.0f + 0xfb);
  for (float h : f.heights) ASSERT_TRUE(h >= 236.0f && h <= 1076.0f) << h;
  // Raw image as the sidecar describes it.
  const PgmImage img = parse(test::read_bytes(path));
  EXPECT_EQ(img.width, 403);
  EXPECT_EQ(img.height, 344);
  EXPECT_EQ(img.maxval, 65535);
}

TEST(Pgm, HeaderCommentsAndEightBitSamples) {
  const PgmImage a = parse(pgm16(2, 1, {1, 65535}, "# made by a test\n"));
  EXPECT_EQ(a.samples, (std::vector<std::uint16_t>{1, 65535}));
  const PgmImage b = parse("P5 #c1\n2#c2\n 2\t#c3\n255\r\x01\x02\x03\xff");
  EXPECT_EQ(b.width, 2);
  EXPECT_EQ(b.height, 2);
  EXPECT_EQ(b.maxval, 255);
  EXPECT_EQ(b.samples, (std::vector<std::uint16_t>{1, 2, 3, 255}));
}

TEST(Pgm, BadHeadersAndSamples) {
  PENUMBRA_STABILITY(
      "PGM files with bad magic, truncated headers or samples, zero or huge sizes, samples over "
      "maxval",
      "LoadError naming the file and the reason", "-");
  auto bad = [](const std::string& bytes, const std::string& reason) {
    expect_load_error([&] { parse(bytes); }, "mem.pgm", reason);
  };
  bad("", "empty file");
  bad("P2\n1 1\n255\n1", "magic is not P5");
  bad("P6\n1 1\n255\nxyz", "magic is not P5");
  bad("P5x 1 1\n255\n1", "garbage after P5");
  bad("P5\n", "truncated header: no width");
  bad("P5\n4 ", "truncated header: no height");
  bad("P5\n4 4\n", "truncated header: no maxval");
  bad("P5\n4 4\n65535", "no whitespace after maxval");
  bad("P5\n-4 4\n255\n", "width is not a decimal number");
  bad("P5\n4x 4\n255\n", "garbage after width");
  bad("P5\n0 4\n255\n", "zero width or height");
  bad("P5\n4 4\n0\n", "maxval is 0");
  bad("P5\n4 4\n65536\n", "maxval exceeds 65535");
  bad("P5\n99999999999 4\n255\n", "width exceeds");
  bad("P5\n65536 65536\n255\n", "image too large");
  bad("P5\n2 2\n255\n\x01\x02\x03", "truncated: 3 of 4 sample bytes");
  bad(pgm16(2, 2, {1, 2, 3}), "truncated: 6 of 8 sample bytes");
  bad(pgm16(2, 1, {1, 2, 3, 4}), "4 bytes after the last sample (wrong dimensions?)");
  bad(std::string("P5\n2 1\n1000\n\x00\x01\x03\xe9", 16), "sample 1 (1001) exceeds maxval 1000");
}

TEST(Pgm, FilesAndSidecars) {
  TempDir dir;
  expect_load_error([&] { load_height_field(dir.file("none.pgm")); }, "none.pgm", "no such file");
  expect_load_error([&] { load_height_field(dir.write("empty.pgm", "")); }, "empty.pgm",
                    "empty file");
  expect_load_error([&] { load_height_field(dir.write("garbage.pgm", std::string(100, '\xfe'))); },
                    "garbage.pgm", "not a binary PGM");
  expect_load_error([&] { load_height_field(dir.write("t.png", "x")); }, "t.png",
                    "unknown height map type");

  // No sidecar: 1 m cells, heights are the samples.
  const data::HeightField plain =
      load_height_field(dir.write("plain.pgm", pgm16(2, 2, {0, 1, 2, 70})));
  EXPECT_FLOAT_EQ(plain.cell_size, 1.0f);
  EXPECT_FLOAT_EQ(plain.at(1, 1), 70.0f);

  dir.write("scaled.pgm", pgm16(2, 2, {0, 1, 2, 3}));
  dir.write(
      "scaled.json",
      R"({"min_elevation": -10, "elevation_scale": 0.5, "cell_size_m": 3, "max_elevation": -8.5})");
  const data::HeightField scaled = load_height_field(dir.file("scaled.pgm"));
  EXPECT_FLOAT_EQ(scaled.at(1, 1), -8.5f);
  EXPECT_FLOAT_EQ(scaled.cell_size, 3.0f);

  dir.write("dims.pgm", pgm16(2, 2, {0, 1, 2, 3}));
  dir.write("dims.json", R"({"width": 2, "height": 3})");
  expect_load_error([&] { load_height_field(dir.file("dims.pgm")); }, "dims.pgm",
                    "wrong dimensions: image is 2x2, sidecar says 2x3");

  dir.write("high.pgm", pgm16(1, 1, {900}));
  dir.write("high.json", R"({"min_elevation": 236, "max_elevation": 1076})");
  expect_load_error([&] { load_height_field(dir.file("high.pgm")); }, "high.pgm",
                    "exceeds max_elevation 1076");

  dir.write("badjson.pgm", pgm16(1, 1, {0}));
  dir.write("badjson.json", R"({"width": 1,)");
  expect_load_error([&] { load_height_field(dir.file("badjson.pgm")); }, "badjson.json",
                    "not valid JSON");
  dir.write("badjson.json", R"({"cell_size_m": -1})");
  expect_load_error([&] { load_height_field(dir.file("badjson.pgm")); }, "badjson.json",
                    "cell size x must be positive");
  dir.write("badjson.json", R"({"width": "wide"})");
  expect_load_error([&] { load_height_field(dir.file("badjson.pgm")); }, "badjson.json",
                    "\"width\" is not a positive integer");
  dir.write("badjson.json", R"([1, 2])");
  expect_load_error([&] { load_height_field(dir.file("badjson.pgm")); }, "badjson.json",
                    "not a JSON object");
}

TEST(Pgm, AnisotropicCellsAreResampledLinearly) {
  HeightSidecar s;
  s.cell_size_x = 1.0;
  s.cell_size_y = 2.0;
  const std::vector<float> v = {0, 10, 4, 14, 8, 18};  // 2 wide, 3 rows 2 m apart
  const data::HeightField f = make_height_field(2, 3, v, s, "mem");
  ASSERT_EQ(f.width, 2);
  ASSERT_EQ(f.height, 5);  // rows at 0, 1, 2, 3, 4 m
  EXPECT_FLOAT_EQ(f.cell_size, 1.0f);
  EXPECT_FLOAT_EQ(f.at(0, 1), 2.0f);
  EXPECT_FLOAT_EQ(f.at(1, 3), 16.0f);
  EXPECT_FLOAT_EQ(f.at(1, 4), 18.0f);
  s.cell_size_x = 3.0;
  s.cell_size_y = 1.0;  // x coarser: columns resampled
  const data::HeightField g = make_height_field(2, 3, v, s, "mem");
  ASSERT_EQ(g.width, 4);
  EXPECT_FLOAT_EQ(g.at(1, 0), 10.0f / 3.0f);
  s.cell_size_y = 1e-300;
  expect_load_error([&] { make_height_field(2, 3, v, s, "mem"); }, "mem",
                    "resampled height field too large");
}

}  // namespace
}  // namespace penumbra::assets
