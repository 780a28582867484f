#include "penumbra/assets/probe_points.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

TEST(ProbePoints, ParsesPositionsCommentsAndBlankLines) {
  const ProbePoints p = parse_probe_points(
      "# a probe cloud\n\n1 2 3\n  -0.5\t+4e-1 1e3   # trailing comment\r\n\t\n7 8 9", 3, "p.txt");
  ASSERT_EQ(p.positions.size(), 3u);
  EXPECT_EQ(p.positions[0], glm::vec3(1, 2, 3));
  EXPECT_EQ(p.positions[1], glm::vec3(-0.5f, 0.4f, 1000));
  EXPECT_EQ(p.positions[2], glm::vec3(7, 8, 9));  // no final newline
  EXPECT_TRUE(p.sh.empty());
  EXPECT_TRUE(parse_probe_points("# nothing\n\n", 2, "p.txt").positions.empty());
}

TEST(ProbePoints, ParsesShAfterThePosition) {
  std::string text;
  for (int probe = 0; probe < 2; ++probe) {
    text += std::to_string(probe) + " 0 0";
    for (int i = 0; i < 12; ++i) text.append(" ").append(std::to_string(probe * 100 + i));
    text += "\n";
  }
  const ProbePoints p = parse_probe_points(text, 2, "p.txt");
  ASSERT_EQ(p.positions.size(), 2u);
  ASSERT_EQ(p.sh.size(), 24u);
  EXPECT_EQ(p.sh[0], 0.0f);
  EXPECT_EQ(p.sh[13], 101.0f);
  EXPECT_EQ(p.sh[23], 111.0f);
}

TEST(ProbePoints, RejectsMalformedLinesNamingTheLine) {
  PENUMBRA_STABILITY("malformed probe point lines", "std::invalid_argument naming the line", "-");
  const auto rejects = [](const std::string& text, const std::string& reason) {
    expect_load_error([&] { parse_probe_points(text, 3, "points.txt"); }, "points.txt", reason);
  };
  rejects("0 0 0\n1 2\n", "line 2: 2 values (expected x y z, or x y z and 27 SH coefficients");
  rejects("0 0 0\n\n# c\n1 2 3 4\n", "line 4: 4 values");
  rejects("0 0 0\n1 a 3\n", "line 2: 'a' is not a number");
  rejects("1,2,3\n", "line 1: '1,2,3' is not a number");
  rejects("1 2 3x\n", "line 1: '3x' is not a number");
  rejects("0 0 0\n0 nan 1\n", "line 2: value 2 ('nan') is not finite");
  rejects("0 0 0\r\n0 0 -inf\r\n", "line 2: value 3 ('-inf') is not finite");
  rejects("1e39 0 0\n", "line 1: value 1 ('1e39') is outside the float range");
  rejects("1e999 0 0\n", "line 1: value 1 ('1e999') is outside the float range");
  std::string sh_line = "0 0 0";
  for (int i = 0; i < 27; ++i) sh_line += " 1";
  rejects("0 0 0\n" + sh_line + "\n", "line 2: SH coefficients, but line 1 has none");
  rejects("\n" + sh_line + "\n1 1 1\n", "line 3: no SH coefficients, but line 2 has them");
  EXPECT_THROW(parse_probe_points("0 0 0\n", 5, "points.txt"), std::invalid_argument);
}

TEST(ProbePoints, LoadsFilesAndNamesThemOnError) {
  PENUMBRA_STABILITY("a missing probe point file", "an error naming the file", "-");
  test::TempDir dir;
  const auto path = dir.write("cloud.txt", "0 0 0\n1 0 0\n");
  EXPECT_EQ(load_probe_points(path, 3).positions.size(), 2u);
  expect_load_error([&] { load_probe_points(dir.file("none.txt"), 3); }, "none.txt",
                    "no such file");
  expect_load_error([&] { load_probe_points(dir.write("empty.txt", ""), 3); }, "empty.txt",
                    "empty file");
  const auto bad = dir.write("bad.txt", "0 0 0\n0 0 x\n");
  expect_load_error([&] { load_probe_points(bad, 3); }, bad.string(), "line 2: 'x'");
}

}  // namespace
}  // namespace penumbra::assets
