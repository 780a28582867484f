#include "file_io.h"

#include <gtest/gtest.h>

#include "common/stability.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_load_error;

TEST(FileIo, ReadsWholeFilesAndNamesTheFileOnError) {
  PENUMBRA_STABILITY("a missing or unreadable file", "an error naming the file", "-");
  test::TempDir dir;
  const auto path = dir.write("bytes.bin", std::string("a\0b\xff", 4));
  EXPECT_EQ(detail::read_file(path), (std::vector<unsigned char>{'a', 0, 'b', 0xff}));
  EXPECT_EQ(detail::require_file(path), 4u);
  expect_load_error([&] { detail::read_file(dir.file("none")); }, "none", "no such file");
  expect_load_error([&] { detail::read_file(dir.write("empty", "")); }, "empty", "empty file");
  expect_load_error([&] { detail::read_file(dir.file("")); }, dir.file("").string(),
                    "not a regular file");
}

}  // namespace
}  // namespace penumbra::assets
