// The stability registry (stability.h): the record a PENUMBRA_STABILITY call writes, its
// measurements, escaping and checksum. scripts/stability_table.py reads these records
// (tests/common/check_stability_table.py checks that side).
#include "common/stability.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

namespace penumbra::test::stability {
namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

class StabilityRegistry : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("penumbra_stability_test_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    ::setenv("PENUMBRA_STABILITY_DIR", dir_.c_str(), 1);
  }
  void TearDown() override {
    ::unsetenv("PENUMBRA_STABILITY_DIR");
    std::filesystem::remove_all(dir_);
  }
  std::filesystem::path dir_;
};

TEST_F(StabilityRegistry, ACallWritesOneRecordWithItsMeasurements) {
  const int line = __LINE__ + 1;
  PENUMBRA_STABILITY("a \"quoted\" input\\n", "what | happens\n", "none");
  const auto path = dir_ / ("StabilityRegistry.ACallWritesOneRecordWithItsMeasurements@" +
                            std::to_string(line) + ".json");
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  std::string text = read(path);
  EXPECT_NE(text.find(R"("input":"a \"quoted\" input\\n")"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("behaviour":"what | happens\u000a")"), std::string::npos) << text;
  EXPECT_NE(text.find("\"line\":" + std::to_string(line)), std::string::npos) << text;
  EXPECT_NE(text.find("\"measured\":[]"), std::string::npos);

  PENUMBRA_STABILITY_MEASURE("max error", 0.125);
  PENUMBRA_STABILITY_MEASURE("nan", std::nan(""));
  text = read(path);
  EXPECT_NE(text.find(R"({"what":"max error","value":0.125})"), std::string::npos) << text;
  EXPECT_NE(text.find(R"({"what":"nan","value":null})"), std::string::npos) << text;
  // Line 2 is the CRC-32 of line 1 (zlib's: crc32("123456789") = cbf43926).
  EXPECT_EQ(crc32("123456789"), 0xcbf43926u);
  const std::string first = text.substr(0, text.find('\n'));
  char expected[32];
  std::snprintf(expected, sizeof expected, "crc32 %08x\n", crc32(first));
  EXPECT_EQ(text.substr(first.size() + 1), expected);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp")) << "renamed, not left behind";
}

TEST_F(StabilityRegistry, SeveralCallsAreSeveralRecords) {
  PENUMBRA_STABILITY("one", "a", "-");
  PENUMBRA_STABILITY("two", "b", "-");
  PENUMBRA_STABILITY_MEASURE("of two", 2);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir_)) {
    ++files;
    const std::string text = read(e.path());
    EXPECT_EQ(text.find("of two") != std::string::npos, text.find("\"two\"") != std::string::npos)
        << "a measurement belongs to the last call";
  }
  EXPECT_EQ(files, 2);
}

}  // namespace
}  // namespace penumbra::test::stability
