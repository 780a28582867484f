#include "penumbra/render/image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "common/stability.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

ImageRgba8 gradient(int w, int h) {
  // Sized first and written by index: gcc 12 at -O3 flags vector::insert of an
  // initializer_list here with a false -Wstringop-overflow.
  ImageRgba8 img{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixels.data() + 4 * (static_cast<std::size_t>(y) * w + x);
      p[0] = static_cast<std::uint8_t>(x * 20);
      p[1] = static_cast<std::uint8_t>(y * 30);
      p[2] = 77;
      p[3] = 255;
    }
  }
  return img;
}

TEST(Image, PngRoundTripIsExactAndLeavesNoTemporaryFile) {
  const std::string dir = test::output_dir() + "/image_test";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/round_trip.png";
  const ImageRgba8 img = gradient(7, 5);
  write_png(path, img);
  const ImageRgba8 back = read_png(path);
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.pixels, img.pixels);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().extension(), ".png") << "left behind: " << e.path();
}

TEST(Image, ErrorsNameThePath) {
  PENUMBRA_STABILITY("a missing PNG, an unwritable path, an image of no pixels",
                     "an error naming the path", "-");
  EXPECT_THROW(read_png("/nonexistent/x.png"), std::runtime_error);
  try {
    write_png("/nonexistent/dir/x.png", gradient(2, 2));
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_png(test::output_dir() + "/bad.png", ImageRgba8{2, 2, {}}),
               std::runtime_error);
}

TEST(Image, ComparisonCountsPixelsBeyondToleranceAndMarksThemInTheDiff) {
  const ImageRgba8 a = gradient(10, 10);
  ImageRgba8 b = a;
  b.pixels[0] += 3;            // within tolerance 3
  b.pixels[4 * 11 + 1] += 4;   // pixel 11 differs
  b.pixels[4 * 50 + 2] -= 50;  // pixel 50 differs
  b.pixels[4 * 60 + 3] = 0;    // alpha is ignored
  const ImageComparison c = compare_images(b, a, 3);
  ASSERT_TRUE(c.same_size);
  EXPECT_EQ(c.pixels, 100u);
  EXPECT_EQ(c.differing, 2u);
  EXPECT_EQ(c.max_difference, 50);
  EXPECT_DOUBLE_EQ(c.fraction(), 0.02);
  EXPECT_GT(c.diff.pixels[4 * 50 + 0], 200) << "large differences are bright red";
  EXPECT_EQ(c.diff.pixels[4 * 50 + 1], 0);
  EXPECT_EQ(c.diff.pixels[4 * 0 + 1], c.diff.pixels[4 * 0 + 0]) << "matching pixels are grey";
  EXPECT_FALSE(compare_images(gradient(10, 9), a, 3).same_size);
}

}  // namespace
}  // namespace penumbra::render
