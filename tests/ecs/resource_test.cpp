#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {

struct Settings {
  int quality = 2;
};
struct Missing {};

TEST(Resource, EmplaceGetReplaceRemove) {
  World w;
  EXPECT_EQ(w.try_resource<Settings>(), nullptr);
  w.emplace_resource<Settings>().quality = 3;
  EXPECT_EQ(w.resource<Settings>().quality, 3);
  w.emplace_resource<Settings>(Settings{7});
  EXPECT_EQ(w.resource<Settings>().quality, 7);
  EXPECT_TRUE(w.remove_resource<Settings>());
  EXPECT_FALSE(w.remove_resource<Settings>());
}

TEST(Resource, MissingResourceErrorNamesTheType) {
  PENUMBRA_STABILITY("a missing resource", "an error naming the type", "-");
  World w;
  try {
    w.resource<Missing>();
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("Missing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::ecs
