#include "penumbra/ecs/access_check.h"

#include <gtest/gtest.h>

#include <string>

#include "common/stability.h"
#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {

struct Read {
  int v = 0;
};
struct Written {
  int v = 0;
};
struct Undeclared {
  int v = 0;
};

// A world with one entity holding all three, and all three as resources.
struct Fixture {
  World world;
  Entity e;
  TypeSet reads = type_set<Read>();
  TypeSet writes = type_set<Written>();
  DeclaredAccess access{"mover", &reads, &writes};
  Fixture() {
    e = world.create_with(Read{}, Written{}, Undeclared{});
    world.emplace_resource<Read>();
    world.emplace_resource<Written>();
    world.emplace_resource<Undeclared>();
  }
};

std::string message_of(auto&& f) {
  try {
    f();
  } catch (const AccessViolation& v) {
    return v.what();
  }
  return "";
}

class AccessCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    if constexpr (!kAccessChecks) GTEST_SKIP() << "access checks are compiled out (NDEBUG)";
  }
};

TEST_F(AccessCheck, NothingIsCheckedOutsideASystem) {
  Fixture f;
  EXPECT_EQ(current_access(), nullptr);
  EXPECT_NO_THROW(f.world.query<Undeclared>().each([](Undeclared&) {}));
  EXPECT_NE(f.world.get_mut<Undeclared>(f.e), nullptr);
  EXPECT_NO_THROW(f.world.resource<Undeclared>());
  EXPECT_NO_THROW(f.world.create());
}

TEST_F(AccessCheck, DeclaredReadsAndWritesPass) {
  Fixture f;
  AccessScope scope(&f.access);
  EXPECT_NO_THROW((f.world.query<const Read, Written>().each([](const Read&, Written&) {})));
  EXPECT_NO_THROW(f.world.query<const Written>().each([](const Written&) {}));  // write => read
  EXPECT_NE(f.world.get<Read>(f.e), nullptr);
  EXPECT_NE(f.world.get_mut<Written>(f.e), nullptr);
  EXPECT_TRUE(f.world.has<Read>(f.e));
  EXPECT_NO_THROW(f.world.resource<const Read>());
  EXPECT_NO_THROW(f.world.resource<Written>());
  EXPECT_NE(f.world.try_resource<const Written>(), nullptr);
}

TEST_F(AccessCheck, UndeclaredAccessThrowsNamingSystemAndType) {
  Fixture f;
  AccessScope scope(&f.access);
  const std::string m = message_of([&] { f.world.query<const Undeclared>(); });
  EXPECT_NE(m.find("'mover'"), std::string::npos) << m;
  EXPECT_NE(m.find("reads<>()"), std::string::npos) << m;
  EXPECT_NE(m.find("Undeclared"), std::string::npos) << m;
  EXPECT_THROW(f.world.get<Undeclared>(f.e), AccessViolation);
  EXPECT_THROW(f.world.has<Undeclared>(f.e), AccessViolation);
  EXPECT_THROW(f.world.try_resource<const Undeclared>(), AccessViolation);
}

TEST_F(AccessCheck, WritingWhatWasDeclaredReadThrows) {
  Fixture f;
  AccessScope scope(&f.access);
  const std::string m = message_of([&] { f.world.query<Read>(); });
  EXPECT_NE(m.find("writes<>()"), std::string::npos) << m;
  EXPECT_NE(m.find("Read"), std::string::npos) << m;
  EXPECT_THROW(f.world.get_mut<Read>(f.e), AccessViolation);
  EXPECT_THROW(f.world.resource<Read>(), AccessViolation);  // non-const: a write
}

TEST_F(AccessCheck, StructuralChangesInsideASystemThrow) {
  PENUMBRA_STABILITY("structural changes inside a system",
                     "AccessViolation naming the call; the world unchanged", "use command buffers");
  Fixture f;
  AccessScope scope(&f.access);
  EXPECT_NE(message_of([&] { f.world.create(); }).find("World::create"), std::string::npos);
  EXPECT_THROW(f.world.create_with(Written{}), AccessViolation);
  EXPECT_THROW(f.world.destroy(f.e), AccessViolation);
  EXPECT_THROW(f.world.add(f.e, Written{}), AccessViolation);
  EXPECT_THROW(f.world.remove<Written>(f.e), AccessViolation);
  EXPECT_THROW(f.world.emplace_resource<Written>(), AccessViolation);
  EXPECT_THROW(f.world.remove_resource<Written>(), AccessViolation);
  EXPECT_TRUE(f.world.alive(f.e));
}

TEST_F(AccessCheck, ScopesNestAndRestore) {
  Fixture f;
  TypeSet none;
  DeclaredAccess other{"other", &none, &f.reads};
  {
    AccessScope outer(&f.access);
    {
      AccessScope inner(&other);
      EXPECT_EQ(current_access(), &other);
      EXPECT_NO_THROW(f.world.get_mut<Read>(f.e));
      EXPECT_THROW(f.world.get<Written>(f.e), AccessViolation);
    }
    EXPECT_EQ(current_access(), &f.access);
    EXPECT_THROW(f.world.get_mut<Read>(f.e), AccessViolation);
  }
  EXPECT_EQ(current_access(), nullptr);
}

}  // namespace
}  // namespace penumbra::ecs
