#include "penumbra/ecs/type_info.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace penumbra::ecs {
namespace {

struct Alpha {
  int v;
};
struct Beta {
  std::string s;
};

TEST(TypeInfo, QualifiersShareOneId) {
  EXPECT_EQ(type_id<Alpha>(), type_id<const Alpha>());
  EXPECT_EQ(type_id<Alpha>(), type_id<Alpha&>());
  EXPECT_NE(type_id<Alpha>(), type_id<Beta>());
  const TypeSet s = type_set<Alpha, const Beta>();
  EXPECT_TRUE(s.test(type_id<Alpha>()));
  EXPECT_TRUE(s.test(type_id<Beta>()));
  EXPECT_EQ(s.count(), 2u);
}

TEST(TypeInfo, NameSizeAndAlignment) {
  const TypeInfo& info = type_info(type_id<Alpha>());
  EXPECT_NE(info.name.find("Alpha"), std::string_view::npos) << info.name;
  EXPECT_EQ(info.size, sizeof(Alpha));
  EXPECT_EQ(info.align, alignof(Alpha));
  EXPECT_TRUE(info.trivially_relocatable);
  EXPECT_FALSE(type_info(type_id<Beta>()).trivially_relocatable);
}

TEST(TypeInfo, RelocateMovesAndDestroysSource) {
  auto owner = std::make_shared<int>(1);
  alignas(std::shared_ptr<int>) unsigned char a[sizeof(std::shared_ptr<int>)];
  alignas(std::shared_ptr<int>) unsigned char b[sizeof(std::shared_ptr<int>)];
  const TypeInfo& info = type_info(type_id<std::shared_ptr<int>>());
  ::new (a) std::shared_ptr<int>(owner);
  EXPECT_EQ(owner.use_count(), 2);
  info.relocate(b, a);  // a is destroyed, b owns the reference
  EXPECT_EQ(owner.use_count(), 2);
  info.move_construct(a, b);  // b is moved-from but alive
  EXPECT_EQ(owner.use_count(), 2);
  info.destroy(b);
  info.destroy(a);
  EXPECT_EQ(owner.use_count(), 1);
}

}  // namespace
}  // namespace penumbra::ecs
