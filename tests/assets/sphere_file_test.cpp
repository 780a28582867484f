#include "penumbra/assets/sphere_file.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/stability.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

SphereSetFile sample_set() {
  SphereSetFile s;
  s.spheres = {{{0.1f, 0.2f, 0.3f}, 1.0f, -1},
               {{-0.4f, 0.0f, 0.25f}, 0.5f, 0},
               {{0.0f, -0.5f, 0.1f}, 0.25f, 1},
               {{3.0f, 2.0f, 1.0f}, 0.0f, -1}};
  s.method = SphereFitMethod::kVariational;
  s.outside_volume_ratio = 0.34375;
  s.coverage = 0.999;
  s.source_model = "bunny.glb";
  return s;
}

void expect_same_spheres(const SphereSetFile& a, const SphereSetFile& b) {
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    EXPECT_EQ(a.spheres[i].centre, b.spheres[i].centre) << i;
    EXPECT_EQ(a.spheres[i].radius, b.spheres[i].radius) << i;
    EXPECT_EQ(a.spheres[i].parent, b.spheres[i].parent) << i;
  }
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.outside_volume_ratio, b.outside_volume_ratio);
  EXPECT_EQ(a.coverage, b.coverage);
  EXPECT_EQ(a.source_model, b.source_model);
}

using test::as_string;
using test::put_u32;
using test::reseal;

void put_f64(std::vector<unsigned char>& b, std::size_t at, double v) {
  const auto u = std::bit_cast<std::uint64_t>(v);
  for (int i = 0; i < 8; ++i)
    b[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(u >> (8 * i));
}

// Offset of sphere i's field (0..4: x, y, z, radius, parent) in sample_set()'s bytes.
std::size_t sphere_field(std::size_t i, std::size_t field) {
  return 36 + std::string("bunny.glb").size() + 20 * i + 4 * field;
}

TEST(SphereFile, Fnv1a64KnownValues) {
  const auto h = [](const std::string& s) {
    return fnv1a64({reinterpret_cast<const unsigned char*>(s.data()), s.size()});
  };
  EXPECT_EQ(h(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(h("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(h("foobar"), 0x85944171f73967e8ull);
}

TEST(SphereFile, LayoutIsTheDocumentedOne) {
  const SphereSetFile s = sample_set();
  const auto b = encode_sphere_file(s);
  ASSERT_EQ(b.size(), 44 + s.source_model.size() + 20 * s.spheres.size());
  EXPECT_EQ(std::memcmp(b.data(), "PSPH", 4), 0);
  EXPECT_EQ(b[4], 1);   // version 1, little-endian
  EXPECT_EQ(b[8], 4);   // count
  EXPECT_EQ(b[12], 2);  // variational
  EXPECT_EQ(b[32], s.source_model.size());
  float r = 0;
  std::memcpy(&r, b.data() + sphere_field(1, 3), 4);
  EXPECT_EQ(r, 0.5f);
}

TEST(SphereFile, RoundTripsThroughDiskAndMemory) {
  test::TempDir dir;
  const SphereSetFile s = sample_set();
  const auto path = dir.file("set.psph");
  write_sphere_file(path, s);
  expect_same_spheres(load_sphere_file(path), s);
  expect_same_spheres(parse_sphere_file(encode_sphere_file(s), "mem"), s);
  // Edge values survive bit for bit: an empty set, no name, the extreme figures.
  SphereSetFile e;
  e.outside_volume_ratio = -1;
  e.coverage = 0;
  e.spheres = {{{-0.0f, std::numeric_limits<float>::max(), 1e-30f}, 0.0f, -1}};
  write_sphere_file(path, e);
  expect_same_spheres(load_sphere_file(path), e);
  e.spheres.clear();
  expect_same_spheres(parse_sphere_file(encode_sphere_file(e), "mem"), e);
}

TEST(SphereFile, AtomicWriteLeavesNoTemporaryFile) {
  test::TempDir dir;
  const auto path = dir.file("set.psph");
  SphereSetFile s = sample_set();
  write_sphere_file(path, s);
  s.spheres.resize(1);
  s.source_model = "suzi.glb";
  write_sphere_file(path, s);  // replaces the old file
  expect_same_spheres(load_sphere_file(path), s);
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir.file("")))
    names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"set.psph"});

  // A failed write names the file and leaves nothing behind: a missing folder, and a target
  // that is a folder (the rename fails after the temporary file was written).
  const auto missing = dir.file("no_such_dir") / "set.psph";
  try {
    write_sphere_file(missing, s);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  std::filesystem::create_directory(dir.file("taken"));
  std::filesystem::create_directory(dir.file("taken") / "child");  // rename cannot replace it
  EXPECT_THROW(write_sphere_file(dir.file("taken"), s), std::runtime_error);
  names.clear();
  for (const auto& e : std::filesystem::directory_iterator(dir.file("")))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"set.psph", "taken"}));
}

TEST(SphereFile, WriterRejectsWhatTheReaderWould) {
  PENUMBRA_STABILITY("a sphere set the reader would reject (a parent cycle, NaN)",
                     "std::invalid_argument; no file written", "-");
  test::TempDir dir;
  const auto bad = [&](auto edit) {
    SphereSetFile s = sample_set();
    edit(s);
    EXPECT_THROW(encode_sphere_file(s), std::invalid_argument);
    EXPECT_THROW(write_sphere_file(dir.file("bad.psph"), s), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.psph")));
  };
  bad([](SphereSetFile& s) { s.spheres[1].centre.y = std::nanf(""); });
  bad([](SphereSetFile& s) { s.spheres[0].radius = -1; });
  bad([](SphereSetFile& s) { s.spheres[0].radius = std::numeric_limits<float>::infinity(); });
  bad([](SphereSetFile& s) { s.spheres[0].parent = 2; });  // 0 -> 2 -> 1 -> 0
  bad([](SphereSetFile& s) { s.spheres[2].parent = 2; });
  bad([](SphereSetFile& s) { s.spheres[2].parent = 4; });
  bad([](SphereSetFile& s) { s.coverage = 1.5; });
  bad([](SphereSetFile& s) { s.outside_volume_ratio = std::nan(""); });
  bad([](SphereSetFile& s) { s.method = static_cast<SphereFitMethod>(3); });
  bad([](SphereSetFile& s) { s.source_model = std::string(5000, 'x'); });
}

TEST(SphereFile, EveryCorruptionIsRejectedNamingTheFile) {
  PENUMBRA_STABILITY("a sphere file with any bit flipped or truncated", "rejected naming the file",
                     "-");
  test::TempDir dir;
  const std::vector<unsigned char> good = encode_sphere_file(sample_set());
  int n = 0;
  const auto rejects = [&](std::vector<unsigned char> bytes, const std::string& reason) {
    const std::string name = "case" + std::to_string(n++) + ".psph";
    const auto path = dir.write(name, as_string(bytes));
    expect_load_error([&] { load_sphere_file(path); }, path.string(), reason);
  };
  rejects({}, "empty file");
  expect_load_error([&] { load_sphere_file(dir.file("missing.psph")); }, "missing.psph",
                    "no such file");
  auto b = good;
  b[3] = 'X';
  rejects(b, "not a sphere file");
  b = good;
  put_u32(b, 4, 2);
  rejects(reseal(b), "unsupported version 2");
  rejects({good.begin(), good.begin() + 6}, "truncated");
  rejects({good.begin(), good.begin() + 30}, "truncated");
  rejects({good.begin(), good.end() - 1}, "truncated");
  b = good;
  b.push_back(0);
  rejects(b, "1 trailing bytes");
  b = good;
  b[sphere_field(2, 3)] ^= 0x01;  // one bit of a radius
  rejects(b, "checksum mismatch");
  b = good;
  b.back() ^= 0x80;
  rejects(b, "checksum mismatch");
  b = good;
  put_u32(b, sphere_field(1, 3), std::bit_cast<std::uint32_t>(std::nanf("")));
  rejects(reseal(b), "sphere 1: non-finite radius");
  b = good;
  put_u32(b, sphere_field(2, 0),
          std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity()));
  rejects(reseal(b), "sphere 2: non-finite centre");
  b = good;
  put_u32(b, sphere_field(0, 3), std::bit_cast<std::uint32_t>(-0.5f));
  rejects(reseal(b), "sphere 0: negative radius");
  b = good;
  put_u32(b, sphere_field(3, 4), 7);
  rejects(reseal(b), "sphere 3: parent 7 out of range");
  b = good;
  put_u32(b, sphere_field(0, 4), 2);
  rejects(reseal(b), "cyclic parent chain");
  b = good;
  put_u32(b, 12, 9);
  rejects(reseal(b), "unknown fit method 9");
  b = good;
  put_f64(b, 16, std::numeric_limits<double>::infinity());
  rejects(reseal(b), "outside volume ratio");
  b = good;
  put_f64(b, 24, -0.25);
  rejects(reseal(b), "coverage");
  b = good;
  put_u32(b, 8, 0xffffffffu);
  rejects(reseal(b), "too many spheres");
  b = good;
  put_u32(b, 32, 0x7fffffffu);
  rejects(reseal(b), "source model name too long");
  b = good;
  put_u32(b, 8, 5);  // one sphere more than the bytes hold
  rejects(reseal(b), "truncated");
}

}  // namespace
}  // namespace penumbra::assets
