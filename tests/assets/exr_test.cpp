#include "penumbra/assets/exr.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "common/stability.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;
using test::TempDir;

// Writes a float (or half) EXR with the given channels over a data window starting at (x0, y0).
void write_exr(const std::filesystem::path& path, int w, int h,
               const std::map<std::string, std::vector<float>>& channels,
               Imf::PixelType type = Imf::FLOAT, int x0 = 0, int y0 = 0,
               Imf::Compression compression = Imf::ZIP_COMPRESSION) {
  Imf::Header header(Imath::Box2i({x0, y0}, {x0 + w - 1, y0 + h - 1}),
                     Imath::Box2i({x0, y0}, {x0 + w - 1, y0 + h - 1}));
  header.compression() = compression;
  std::map<std::string, std::vector<Imath::half>> halves;
  Imf::FrameBuffer fb;
  const Imath::Box2i dw = header.dataWindow();
  for (const auto& [name, values] : channels) {
    header.channels().insert(name, Imf::Channel(type));
    if (type == Imf::HALF) {
      auto& hv = halves[name];
      hv.assign(values.begin(), values.end());
      fb.insert(name, Imf::Slice::Make(Imf::HALF, hv.data(), dw, sizeof(Imath::half)));
    } else {
      fb.insert(name, Imf::Slice::Make(Imf::FLOAT, values.data(), dw, sizeof(float)));
    }
  }
  Imf::OutputFile out(path.c_str(), header);
  out.setFrameBuffer(fb);
  out.writePixels(h);
}

const char* const kMaps[] = {"apartment", "bridge", "city",    "dawn",  "esplanade",
                             "forest",    "hall",   "lab",     "lobby", "park",
                             "sky",       "studio", "sunrise", "sunset"};

TEST(Exr, AllSharedEnvironmentMapsLoad) {
  for (const char* name : kMaps) {
    const auto path = test::shared_data() / "hdri" / (std::string(name) + ".exr");
    const auto t0 = std::chrono::steady_clock::now();
    data::EnvironmentMap m;
    ASSERT_NO_THROW(m = load_environment_map(path)) << path;  // a missing file fails here
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(m.width, 512) << name;
    EXPECT_EQ(m.height, 256) << name;
    ASSERT_EQ(m.rgb.size(), 512u * 256u * 3u);
    float hi = 0;
    for (float v : m.rgb) {
      ASSERT_TRUE(std::isfinite(v) && v >= 0) << name << " " << v;
      hi = std::max(hi, v);
    }
    EXPECT_GT(hi, 1.0f) << name << " is HDR";
    EXPECT_EQ(m.source, path.string());
    std::printf("  %-10s %.2f ms, max %.6g, %zu negative values clamped\n", name, ms, hi,
                m.clamped_values);
  }
}

TEST(Exr, RowZeroIsTheTopRowAndDataWindowOffsetIsIgnored) {
  TempDir dir;
  const int w = 4, h = 3;
  std::vector<float> r(w * h, 0.0f), g(w * h, 0.5f), b(w * h, 0.25f);
  for (int x = 0; x < w; ++x) r[x] = 10.0f + x;  // first (top) row
  const auto path = dir.file("top.exr");
  write_exr(path, w, h, {{"R", r}, {"G", g}, {"B", b}}, Imf::HALF, -5, 7);
  const data::EnvironmentMap m = load_environment_map(path);
  ASSERT_EQ(m.width, w);
  ASSERT_EQ(m.height, h);
  EXPECT_FLOAT_EQ(m.texel(2, 0)[0], 12.0f);
  EXPECT_FLOAT_EQ(m.texel(2, 1)[0], 0.0f);
  EXPECT_FLOAT_EQ(m.texel(3, 2)[1], 0.5f);
  EXPECT_FLOAT_EQ(m.texel(3, 2)[2], 0.25f);
  EXPECT_EQ(m.clamped_values, 0u);
}

TEST(Exr, LuminanceOnlyMapIsGrey) {
  TempDir dir;
  const auto path = dir.file("y.exr");
  write_exr(path, 2, 2, {{"Y", {1, 2, 3, 4}}});
  const data::EnvironmentMap m = load_environment_map(path);
  EXPECT_FLOAT_EQ(m.texel(1, 1)[0], 4.0f);
  EXPECT_FLOAT_EQ(m.texel(1, 1)[1], 4.0f);
  EXPECT_FLOAT_EQ(m.texel(1, 1)[2], 4.0f);
}

TEST(Exr, NegativeLobesAreClampedKeepingEachBlocksEnergy) {
  PENUMBRA_STABILITY("negative texels (ringing around a sun) in an EXR map",
                     "clamped to 0, each block's energy kept, counted", "-");
  TempDir dir;
  const int w = 16, h = 8;
  std::vector<float> r(w * h, 1.0f), g(w * h, 1.0f), b(w * h, 1.0f);
  r[3 * w + 2] = 100.0f;  // a "sun" in block (0, 0) with ringing around it
  r[3 * w + 3] = -10.0f;
  r[4 * w + 2] = -5.0f;
  r[2 * w + 12] = -3.0f;  // block (1, 0): all others 1, total still positive
  const auto path = dir.file("ring.exr");
  write_exr(path, w, h, {{"R", r}, {"G", g}, {"B", b}});
  const data::EnvironmentMap m = load_environment_map(path);
  EXPECT_EQ(m.clamped_values, 3u);
  auto block_sum = [&](const std::vector<float>& v, bool from_map, int bx) {
    double s = 0;
    for (int y = 0; y < 8; ++y) {
      const double wy =
          std::cos(std::numbers::pi * y / h) - std::cos(std::numbers::pi * (y + 1) / h);
      for (int x = bx; x < bx + 8; ++x) s += wy * (from_map ? m.texel(x, y)[0] : v[y * w + x]);
    }
    return s;
  };
  for (int bx : {0, 8}) EXPECT_NEAR(block_sum(r, true, bx), block_sum(r, false, bx), 1e-4) << bx;
  for (float v : m.rgb) EXPECT_GE(v, 0.0f);
  EXPECT_FLOAT_EQ(m.texel(3, 3)[0], 0.0f);
  EXPECT_FLOAT_EQ(m.texel(5, 5)[1], 1.0f);  // other channels untouched
}

TEST(Exr, BadFilesThrowLoadErrorNamingFileAndReason) {
  PENUMBRA_STABILITY("missing, garbage and truncated EXR files",
                     "LoadError naming the file and the reason", "-");
  TempDir dir;
  expect_load_error([&] { load_environment_map(dir.file("missing.exr")); }, "missing.exr",
                    "no such file");
  const auto empty = dir.write("empty.exr", "");
  expect_load_error([&] { load_environment_map(empty); }, "empty.exr", "empty file");
  const auto garbage = dir.write("garbage.exr", std::string(4096, 'x'));
  expect_load_error([&] { load_environment_map(garbage); }, "garbage.exr", "OpenEXR");
  expect_load_error([&] { load_environment_map(dir.file("")); }, dir.file("").string(),
                    "not a regular file");

  // A valid map, cut short at several lengths.
  const int w = 64, h = 64;
  std::vector<float> v(w * h);
  for (int i = 0; i < w * h; ++i) v[i] = static_cast<float>(i % 97) * 0.1f;
  const auto good = dir.file("good.exr");
  write_exr(good, w, h, {{"R", v}, {"G", v}, {"B", v}}, Imf::HALF, 0, 0, Imf::PIZ_COMPRESSION);
  ASSERT_NO_THROW(load_environment_map(good));
  const std::string bytes = test::read_bytes(good);
  for (std::size_t cut : {std::size_t{8}, std::size_t{200}, bytes.size() / 2, bytes.size() - 10}) {
    const auto truncated = dir.write("truncated.exr", bytes.substr(0, cut));
    expect_load_error([&] { load_environment_map(truncated); }, "truncated.exr", "OpenEXR");
  }

  const auto no_rgb = dir.file("depth.exr");
  write_exr(no_rgb, 2, 2, {{"Z", {1, 2, 3, 4}}});
  expect_load_error([&] { load_environment_map(no_rgb); }, "depth.exr", "no R, G, B or Y channels");

  const auto nan = dir.file("nan.exr");
  const float q = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  write_exr(nan, 2, 2, {{"R", {1, q, 1, 1}}, {"G", {1, 1, 1, inf}}, {"B", {1, 1, 1, 1}}});
  expect_load_error([&] { load_environment_map(nan); }, "nan.exr",
                    "2 NaN or infinite values, first at texel (1, 0)");
}

TEST(Exr, SingleChannelHeightMapWithSidecar) {
  TempDir dir;
  const auto path = dir.file("terrain.exr");
  write_exr(path, 3, 2, {{"Y", {0, 1, 2, 3, 4, 5}}});
  dir.write("terrain.json",
            R"({"width": 3, "height": 2, "cell_size_m": 2.5, "min_elevation": 100})");
  EXPECT_EQ(exr_channel_count(path), 1);
  const data::HeightField f = load_height_field_exr(path);
  EXPECT_EQ(f.width, 3);
  EXPECT_EQ(f.height, 2);
  EXPECT_FLOAT_EQ(f.cell_size, 2.5f);
  EXPECT_FLOAT_EQ(f.at(2, 1), 105.0f);
  EXPECT_FLOAT_EQ(f.at(0, 0), 100.0f);
}

TEST(Exr, BadHeightMaps) {
  PENUMBRA_STABILITY("EXR height maps with NaN, wrong channels or size",
                     "LoadError naming the file", "-");
  TempDir dir;
  const float q = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  const auto nan = dir.file("nan_height.exr");
  write_exr(nan, 2, 2, {{"Z", {0, 1, q, 3}}});
  expect_load_error([&] { load_height_field_exr(nan); }, "nan_height.exr",
                    "NaN or infinite height at sample (0, 1)");
  const auto inf_path = dir.file("inf_height.exr");
  write_exr(inf_path, 2, 2, {{"Z", {0, 1, 2, -inf}}});
  expect_load_error([&] { load_height_field_exr(inf_path); }, "inf_height.exr",
                    "NaN or infinite height at sample (1, 1)");
  const auto rgb = dir.file("rgb.exr");
  write_exr(rgb, 1, 1, {{"R", {1}}, {"G", {1}}, {"B", {1}}});
  expect_load_error([&] { load_height_field_exr(rgb); }, "rgb.exr",
                    "exactly one channel, found 3 (B, G, R)");
  const auto dims = dir.file("dims.exr");
  write_exr(dims, 2, 2, {{"Y", {0, 1, 2, 3}}});
  dir.write("dims.json", R"({"width": 3, "height": 2})");
  expect_load_error([&] { load_height_field_exr(dims); }, "dims.exr",
                    "wrong dimensions: image is 2x2, sidecar says 3x2");
}

}  // namespace
}  // namespace penumbra::assets
