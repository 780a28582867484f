#include "penumbra/assets/probe_cloud_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/stability.h"
#include "probe_cloud_sample.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

void expect_same_cloud(const data::ProbeCloud& a, const data::ProbeCloud& b) {
  EXPECT_EQ(a.bands, b.bands);
  EXPECT_EQ(a.inner_count, b.inner_count);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.cells.size(), b.cells.size());
  const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(bits(a.positions[i][k]), bits(b.positions[i][k])) << i;
      EXPECT_EQ(bits(a.hull_normals[i][k]), bits(b.hull_normals[i][k])) << i;
    }
  ASSERT_EQ(a.sh.size(), b.sh.size());
  for (std::size_t i = 0; i < a.sh.size(); ++i) EXPECT_EQ(bits(a.sh[i]), bits(b.sh[i])) << i;
  for (std::size_t i = 0; i < a.cells.size(); ++i) {
    EXPECT_EQ(a.cells[i].vertices, b.cells[i].vertices) << i;
    EXPECT_EQ(a.cells[i].neighbours, b.cells[i].neighbours) << i;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row)
        EXPECT_EQ(bits(a.transforms[i][col][row]), bits(b.transforms[i][col][row])) << i;
  }
}

using test::as_string;
using test::put_u32;
using test::reseal;
void put_f32(std::vector<unsigned char>& b, std::size_t at, float v) {
  put_u32(b, at, std::bit_cast<std::uint32_t>(v));
}

// Offsets in the bytes of single_tetrahedron_cloud(3) (4 probes, 5 cells; see the header's
// table).
constexpr std::size_t kProbes = 4, kCells = 5, kCoeffs = 27;
constexpr std::size_t kPositions = 24;
constexpr std::size_t kSh = kPositions + 12 * kProbes;
constexpr std::size_t kNormals = kSh + 4 * kCoeffs * kProbes;
constexpr std::size_t kCellIndices = kNormals + 12 * kProbes;
constexpr std::size_t kTransforms = kCellIndices + 32 * kCells;
std::size_t vertex_at(std::size_t cell, std::size_t k) {
  return kCellIndices + 32 * cell + 4 * k;
}
std::size_t neighbour_at(std::size_t cell, std::size_t k) {
  return vertex_at(cell, 4 + k);
}

const float kNan = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

std::vector<std::string> folder_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ProbeCloudFile, SampleCloudIsConsistent) {
  // The hand-built cloud the tests and the corpus use: positive orientation, symmetric links,
  // barycentric transform reproducing the vertices, outer cubic vanishing at t = 0 on the face.
  const data::ProbeCloud c = test::single_tetrahedron_cloud();
  const auto& p = c.positions;
  EXPECT_GT(glm::dot(p[1] - p[0], glm::cross(p[2] - p[0], p[3] - p[0])), 0.0f);
  for (std::size_t i = 0; i < c.cells.size(); ++i)
    for (std::int32_t nb : c.cells[i].neighbours) {
      const auto& back = c.cells[static_cast<std::size_t>(nb)].neighbours;
      EXPECT_NE(std::find(back.begin(), back.end(), static_cast<std::int32_t>(i)), back.end())
          << i << " -> " << nb;
    }
  for (int k = 0; k < 4; ++k) {
    const glm::vec3 l = glm::mat3(c.transforms[0]) *
                        (p[static_cast<std::size_t>(k)] - glm::vec3(c.transforms[0][3]));
    const float l3 = 1 - l.x - l.y - l.z;
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(j < 3 ? l[j] : l3, j == k ? 1.0f : 0.0f, 1e-6f) << k << " " << j;
  }
  for (std::size_t i = 1; i < c.cells.size(); ++i) {
    const auto& v = c.cells[i].vertices;
    const glm::vec3 centroid =
        (p[static_cast<std::size_t>(v[0])] + p[static_cast<std::size_t>(v[1])] +
         p[static_cast<std::size_t>(v[2])]) /
        3.0f;
    const glm::vec4 x(centroid, 1);
    const glm::mat4& m = c.transforms[i];
    const float constant = m[0][3] * x.x + m[1][3] * x.y + m[2][3] * x.z + m[3][3];
    EXPECT_NEAR(constant, 0.0f, 1e-6f) << i;  // the point lies on the triangle at t = 0
    const glm::vec3 out =
        glm::cross(p[static_cast<std::size_t>(v[1])] - p[static_cast<std::size_t>(v[0])],
                   p[static_cast<std::size_t>(v[2])] - p[static_cast<std::size_t>(v[0])]);
    EXPECT_GT(glm::dot(out, centroid - glm::vec3(0.25f)), 0.0f) << i;
  }
  for (const glm::vec3& n : c.hull_normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
}

TEST(ProbeCloudFile, LayoutIsTheDocumentedOne) {
  const data::ProbeCloud c = test::single_tetrahedron_cloud();
  const auto b = encode_probe_cloud_file(c);
  ASSERT_EQ(b.size(), 32 + kProbes * (24 + 12 * 9) + 96 * kCells);
  EXPECT_EQ(b.size(), probe_cloud_file_size(3, kProbes, kCells));
  EXPECT_EQ(std::memcmp(b.data(), "PCLD", 4), 0);
  EXPECT_EQ(b[4], 1);  // version 1, little-endian
  EXPECT_EQ(b[8], 3);  // bands
  EXPECT_EQ(b[12], kProbes);
  EXPECT_EQ(b[16], kCells);
  EXPECT_EQ(b[20], 1);  // inner count
  float f = 0;
  std::memcpy(&f, b.data() + kPositions + 12 * 1, 4);  // probe 1's x
  EXPECT_EQ(f, 1.0f);
  std::memcpy(&f, b.data() + kSh + 4 * (kCoeffs * 2 + 9 * 1 + 0), 4);  // probe 2, green, c0
  EXPECT_EQ(f, c.sh[2 * kCoeffs + 9]);
  std::memcpy(&f, b.data() + kNormals, 4);
  EXPECT_EQ(f, c.hull_normals[0].x);
  std::int32_t v = 0;
  std::memcpy(&v, b.data() + vertex_at(2, 3), 4);
  EXPECT_EQ(v, data::kOuterVertex);
  std::memcpy(&v, b.data() + neighbour_at(1, 0), 4);
  EXPECT_EQ(v, 2);
  std::memcpy(&f, b.data() + kTransforms + 4 * (4 * 3 + 2), 4);  // cell 0, column 3, row 2
  EXPECT_EQ(f, 1.0f);                                            // p3.z
}

TEST(ProbeCloudFile, RoundTripsExactlyThroughDiskAndMemory) {
  test::TempDir dir;
  const auto path = dir.file("cloud.pcld");
  for (int bands = data::kProbeMinBands; bands <= data::kProbeMaxBands; ++bands) {
    const data::ProbeCloud c = test::single_tetrahedron_cloud(bands);
    save_probe_cloud_file(path, c);
    expect_same_cloud(load_probe_cloud_file(path), c);
    expect_same_cloud(parse_probe_cloud_file(encode_probe_cloud_file(c), "mem"), c);
  }
  // Edge values survive bit for bit.
  data::ProbeCloud c = test::single_tetrahedron_cloud(2);
  c.positions[0] = {-0.0f, std::numeric_limits<float>::max(),
                    std::numeric_limits<float>::denorm_min()};
  c.sh[5] = -std::numeric_limits<float>::max();
  save_probe_cloud_file(path, c);
  expect_same_cloud(load_probe_cloud_file(path), c);
}

TEST(ProbeCloudFile, CloudsWithoutCells) {
  // 0 probes (an empty scene) and 3 probes (too few to tetrahedralize) are valid files.
  test::TempDir dir;
  const auto path = dir.file("empty.pcld");
  data::ProbeCloud empty;
  save_probe_cloud_file(path, empty);
  EXPECT_EQ(std::filesystem::file_size(path), 32u);
  const data::ProbeCloud loaded = load_probe_cloud_file(path);
  EXPECT_EQ(loaded.bands, data::kProbeDefaultBands);
  EXPECT_EQ(loaded.probe_count(), 0u);
  EXPECT_TRUE(loaded.cells.empty());
  EXPECT_EQ(loaded.inner_count, 0u);
  data::ProbeCloud three;
  three.bands = 4;
  three.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  three.sh.assign(3 * 48, 0.5f);
  three.hull_normals.assign(3, glm::vec3(0));
  save_probe_cloud_file(path, three);
  expect_same_cloud(load_probe_cloud_file(path), three);
}

TEST(ProbeCloudFile, AtomicWriteLeavesNoTemporaryFile) {
  test::TempDir dir;
  const auto path = dir.file("cloud.pcld");
  save_probe_cloud_file(path, test::single_tetrahedron_cloud(3));
  const data::ProbeCloud second = test::single_tetrahedron_cloud(2);
  save_probe_cloud_file(path, second);  // replaces the old file
  expect_same_cloud(load_probe_cloud_file(path), second);
  EXPECT_EQ(folder_names(dir.file("")), std::vector<std::string>{"cloud.pcld"});

  // Failed writes name the file, leave no temporary file and the old file as it was: a missing
  // folder, a target that is a non-empty folder (the rename fails after the temporary file was
  // written), and a cloud the writer refuses.
  const auto missing = dir.file("no_such_dir") / "cloud.pcld";
  try {
    save_probe_cloud_file(missing, second);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  std::filesystem::create_directory(dir.file("taken"));
  std::filesystem::create_directory(dir.file("taken") / "child");
  EXPECT_THROW(save_probe_cloud_file(dir.file("taken"), second), std::runtime_error);
  data::ProbeCloud bad = test::single_tetrahedron_cloud(3);
  bad.positions[2].y = kNan;
  EXPECT_THROW(save_probe_cloud_file(path, bad), std::invalid_argument);
  EXPECT_EQ(folder_names(dir.file("")), (std::vector<std::string>{"cloud.pcld", "taken"}));
  expect_same_cloud(load_probe_cloud_file(path), second);
}

TEST(ProbeCloudFile, WriterRejectsWhatTheReaderWould) {
  PENUMBRA_STABILITY("a cloud the reader would reject, given to the writer",
                     "std::invalid_argument naming the reason; no file written", "-");
  const auto bad = [](auto edit, const std::string& reason) {
    data::ProbeCloud c = test::single_tetrahedron_cloud();
    edit(c);
    try {
      encode_probe_cloud_file(c);
      ADD_FAILURE() << "no error for " << reason;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  bad([](data::ProbeCloud& c) { c.bands = 5; }, "bands 5 outside 2..4");
  bad([](data::ProbeCloud& c) { c.bands = 1; }, "bands 1 outside 2..4");
  bad([](data::ProbeCloud& c) { c.sh.pop_back(); }, "SH size 107");
  bad([](data::ProbeCloud& c) { c.hull_normals.pop_back(); }, "3 hull normals for 4 probes");
  bad([](data::ProbeCloud& c) { c.transforms.pop_back(); }, "4 transforms for 5 cells");
  bad([](data::ProbeCloud& c) { c.inner_count = 6; }, "inner count 6 above the cell count 5");
  bad([](data::ProbeCloud& c) { c.inner_count = 2; }, "cell 1: outer cell among the inner");
  bad([](data::ProbeCloud& c) { c.inner_count = 0; }, "cell 0: inner tetrahedron after");
  bad([](data::ProbeCloud& c) { c.positions[3].z = kInf; }, "probe 3: non-finite position");
  bad([](data::ProbeCloud& c) { c.hull_normals[1].x = kNan; }, "probe 1: non-finite hull normal");
  bad([](data::ProbeCloud& c) { c.sh[30] = kNan; }, "probe 1: non-finite SH");
  bad([](data::ProbeCloud& c) { c.transforms[4][2][1] = -kInf; }, "cell 4: non-finite transform");
  bad([](data::ProbeCloud& c) { c.cells[0].vertices[2] = 4; }, "cell 0: vertex 4 out of range");
  bad([](data::ProbeCloud& c) { c.cells[3].vertices[0] = -1; }, "cell 3: vertex -1 out of range");
  bad([](data::ProbeCloud& c) { c.cells[2].neighbours[1] = 5; }, "cell 2: neighbour 5 out of");
  bad([](data::ProbeCloud& c) { c.cells[0].neighbours[3] = -1; }, "cell 0: neighbour -1 out of");
}

TEST(ProbeCloudFile, EveryCorruptionIsRejectedNamingTheFile) {
  PENUMBRA_STABILITY("a probe cloud file with any bit flipped, truncated, a foreign magic",
                     "rejected naming the file (checksum, size, magic)", "-");
  test::TempDir dir;
  const std::vector<unsigned char> good = encode_probe_cloud_file(test::single_tetrahedron_cloud());
  int n = 0;
  const auto rejects = [&](std::vector<unsigned char> bytes, const std::string& reason) {
    const std::string name = "case" + std::to_string(n++) + ".pcld";
    const auto path = dir.write(name, as_string(bytes));
    expect_load_error([&] { load_probe_cloud_file(path); }, path.string(), reason);
  };
  rejects({}, "empty file");
  expect_load_error([&] { load_probe_cloud_file(dir.file("missing.pcld")); }, "missing.pcld",
                    "no such file");
  rejects({'P', 'S', 'P', 'H', 1, 0, 0, 0, 0, 0}, "not a probe cloud file");  // a sphere file
  rejects({'{', '"', 'a', '"', ':', '1', '}', '\n'}, "not a probe cloud file");
  auto b = good;
  put_u32(b, 4, 2);
  rejects(reseal(b), "unsupported version 2");
  rejects({good.begin(), good.begin() + 6}, "truncated");
  rejects({good.begin(), good.begin() + 20}, "truncated: 20 of 24 header bytes");
  rejects({good.begin(), good.begin() + 200}, "truncated");
  rejects({good.begin(), good.end() - 1}, "truncated");
  b = good;
  b.push_back(0);
  rejects(b, "1 trailing bytes");
  b = good;
  b[kSh + 13] ^= 0x01;  // one bit of a coefficient
  rejects(b, "checksum mismatch");
  b = good;
  b.back() ^= 0x80;
  rejects(b, "checksum mismatch");
  b = good;
  put_u32(b, 8, 5);
  rejects(reseal(b), "bands 5 outside 2..4");
  b = good;
  put_u32(b, 8, 0);
  rejects(reseal(b), "bands 0 outside 2..4");
  b = good;
  put_u32(b, 12, 0xffffffffu);
  rejects(reseal(b), "too many probes (4294967295, at most 16777216)");
  b = good;
  put_u32(b, 16, kMaxProbeCloudCells + 1);
  rejects(reseal(b), "too many cells");
  b = good;
  put_u32(b, 20, 6);
  rejects(reseal(b), "inner count 6 above the cell count 5");
  b = good;
  put_u32(b, 12, 5);  // one probe more than the bytes hold
  rejects(reseal(b), "truncated");
  b = good;
  put_f32(b, kPositions + 12 * 2 + 4, kNan);
  rejects(reseal(b), "probe 2: non-finite position");
  b = good;
  put_f32(b, kSh + 4 * (kCoeffs * 3 + 20), kInf);
  rejects(reseal(b), "probe 3: non-finite SH coefficient");
  b = good;
  put_f32(b, kNormals + 12 * 1, -kInf);
  rejects(reseal(b), "probe 1: non-finite hull normal");
  b = good;
  put_f32(b, kTransforms + 64 * 3 + 4 * 7, kNan);
  rejects(reseal(b), "cell 3: non-finite transform");
  b = good;
  put_u32(b, vertex_at(0, 1), 4);
  rejects(reseal(b), "cell 0: vertex 4 out of range (4 probes)");
  b = good;
  put_u32(b, vertex_at(2, 0), std::bit_cast<std::uint32_t>(std::int32_t{-7}));
  rejects(reseal(b), "cell 2: vertex -7 out of range");
  b = good;
  put_u32(b, vertex_at(0, 3), std::bit_cast<std::uint32_t>(std::int32_t{-2}));
  rejects(reseal(b), "cell 0: vertex -2 out of range");
  b = good;
  put_u32(b, neighbour_at(4, 2), 5);
  rejects(reseal(b), "cell 4: neighbour 5 out of range (5 cells)");
  b = good;
  put_u32(b, neighbour_at(0, 0), std::bit_cast<std::uint32_t>(data::kOuterVertex));
  rejects(reseal(b), "cell 0: neighbour -1 out of range");
  b = good;
  put_u32(b, vertex_at(0, 3), std::bit_cast<std::uint32_t>(data::kOuterVertex));
  rejects(reseal(b), "cell 0: outer cell among the inner ones");
  b = good;
  put_u32(b, vertex_at(3, 3), 1);
  rejects(reseal(b), "cell 3: inner tetrahedron after the outer cells");
}

// The valid seed files of fuzz_probe_cloud_file are these clouds' bytes. With
// PENUMBRA_WRITE_CORPUS=DIR set, writes them into DIR (engine/assets/fuzz/corpus/
// probe_cloud_file) together with the broken seeds derived from them.
TEST(ProbeCloudFile, FuzzCorpusSeedsAreCurrent) {
  data::ProbeCloud three;
  three.bands = 2;
  three.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  three.sh.assign(3 * 12, 0.25f);
  three.hull_normals.assign(3, glm::vec3(0));
  const std::vector<unsigned char> tetra =
      encode_probe_cloud_file(test::single_tetrahedron_cloud());
  std::vector<std::pair<std::string, std::vector<unsigned char>>> seeds = {
      {"valid_tetrahedron.pcld", tetra},
      {"valid_tetrahedron_2_bands.pcld",
       encode_probe_cloud_file(test::single_tetrahedron_cloud(2))},
      {"valid_tetrahedron_4_bands.pcld",
       encode_probe_cloud_file(test::single_tetrahedron_cloud(4))},
      {"valid_empty.pcld", encode_probe_cloud_file({})},
      {"valid_three_probes.pcld", encode_probe_cloud_file(three)},
  };
  auto b = tetra;
  b.resize(b.size() - 40);
  seeds.emplace_back("truncated_cells.pcld", b);
  seeds.emplace_back("truncated_header.pcld",
                     std::vector<unsigned char>(tetra.begin(), tetra.begin() + 14));
  b = tetra;
  b[kSh + 7] ^= 0x10;
  seeds.emplace_back("bad_checksum.pcld", b);
  seeds.emplace_back("foreign.pcld", std::vector<unsigned char>{'P', 'S', 'P', 'H', 1, 0, 0, 0, 0,
                                                                0, 0, 0});  // a sphere file header
  b = tetra;
  put_u32(b, 4, 2);
  seeds.emplace_back("wrong_version.pcld", reseal(b));
  b = tetra;
  put_u32(b, 8, 9);
  seeds.emplace_back("bands_9.pcld", reseal(b));
  b = tetra;
  put_u32(b, 12, 0x7fffffffu);
  seeds.emplace_back("huge_probe_count.pcld", reseal(b));
  b = tetra;
  put_u32(b, 20, 9);
  seeds.emplace_back("inner_above_cells.pcld", reseal(b));
  b = tetra;
  put_f32(b, kPositions + 4, kNan);
  seeds.emplace_back("nan_position.pcld", reseal(b));
  b = tetra;
  put_u32(b, vertex_at(1, 2), 17);
  seeds.emplace_back("vertex_out_of_range.pcld", reseal(b));
  b = tetra;
  put_u32(b, neighbour_at(3, 1), 0x80000000u);
  seeds.emplace_back("neighbour_out_of_range.pcld", reseal(b));
  b = tetra;
  put_u32(b, vertex_at(4, 3), 0);
  seeds.emplace_back("inner_after_outer.pcld", reseal(b));
  b = tetra;
  b.push_back(0);
  seeds.emplace_back("trailing_bytes.pcld", b);

  if (const char* out = std::getenv("PENUMBRA_WRITE_CORPUS")) {
    for (const auto& [name, bytes] : seeds)
      std::ofstream(std::filesystem::path(out) / name, std::ios::binary)
          .write(reinterpret_cast<const char*>(bytes.data()),
                 static_cast<std::streamsize>(bytes.size()));
  }
  const std::filesystem::path corpus = PENUMBRA_PROBE_CLOUD_CORPUS;
  for (const auto& [name, bytes] : seeds) {
    EXPECT_TRUE(test::read_bytes(corpus / name) == as_string(bytes))
        << name << " differs from the encoder's bytes: rerun this test with "
        << "PENUMBRA_WRITE_CORPUS=" << corpus.string();
    if (name.starts_with("valid_")) {
      EXPECT_NO_THROW(parse_probe_cloud_file(bytes, name)) << name;
    } else {
      EXPECT_THROW(parse_probe_cloud_file(bytes, name), LoadError) << name;
    }
  }
}

}  // namespace
}  // namespace penumbra::assets
