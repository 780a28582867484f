#include "penumbra/ecs/world.h"

#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace penumbra::ecs {
namespace {

struct A {
  int v;
};
struct B {
  double v;
};
struct C {
  std::string v;  // non-trivial: exercises move, relocate and destroy
};
struct Tag {};

TEST(World, AddGetReplaceRemove) {
  World w;
  const Entity e = w.create();
  EXPECT_FALSE(w.has<A>(e));
  w.add(e, A{1});
  w.add(e, C{"hello"});
  ASSERT_NE(w.get<A>(e), nullptr);
  EXPECT_EQ(w.get<A>(e)->v, 1);
  EXPECT_EQ(w.get<C>(e)->v, "hello");
  w.add(e, A{2});  // replace in place
  EXPECT_EQ(w.get<A>(e)->v, 2);
  EXPECT_TRUE(w.remove<A>(e));
  EXPECT_FALSE(w.remove<A>(e));
  EXPECT_EQ(w.get<A>(e), nullptr);
  EXPECT_EQ(w.get<C>(e)->v, "hello") << "other components survive the archetype move";
}

TEST(World, CreateWithPlacesEntityDirectly) {
  World w;
  const Entity e = w.create_with(A{7}, C{"x"}, Tag{});
  EXPECT_EQ(w.get<A>(e)->v, 7);
  EXPECT_EQ(w.get<C>(e)->v, "x");
  EXPECT_TRUE(w.has<Tag>(e));
  EXPECT_FALSE(w.has<B>(e));
}

TEST(World, AddToDeadEntityThrowsNamingTheType) {
  World w;
  const Entity e = w.create();
  w.destroy(e);
  try {
    w.add(e, A{1});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("A"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("not alive"), std::string::npos) << err.what();
  }
}

TEST(World, GetMutStampsChunk) {
  World w;
  const Entity e = w.create_with(A{1});
  w.set_tick(50);
  *w.get_mut<A>(e) = A{2};
  auto q = w.query<const A>();
  ASSERT_EQ(q.prepare(), 1u);
  EXPECT_TRUE(q.chunk(0).changed_since<const A>(49));
  EXPECT_FALSE(q.chunk(0).changed_since<const A>(50));
}

// Random structural sequences checked against a plain reference model.
TEST(World, RandomOperationsMatchReferenceModel) {
  struct Model {
    std::optional<int> a;
    std::optional<double> b;
    std::optional<std::string> c;
    bool tag = false;
  };
  World w;
  std::map<std::uint64_t, std::pair<Entity, Model>> model;
  std::vector<Entity> dead;
  std::mt19937 rng(1234);
  auto pick = [&]() -> std::pair<Entity, Model>& {
    auto it = model.begin();
    std::advance(it, std::uniform_int_distribution<std::size_t>(0, model.size() - 1)(rng));
    return it->second;
  };
  auto check_all = [&] {
    ASSERT_EQ(w.size(), model.size());
    for (auto& [bits, em] : model) {
      const auto& [e, m] = em;
      ASSERT_TRUE(w.alive(e));
      ASSERT_EQ(w.has<A>(e), m.a.has_value());
      if (m.a) {
        ASSERT_EQ(w.get<A>(e)->v, *m.a);
      }
      ASSERT_EQ(w.has<B>(e), m.b.has_value());
      if (m.b) {
        ASSERT_EQ(w.get<B>(e)->v, *m.b);
      }
      ASSERT_EQ(w.has<C>(e), m.c.has_value());
      if (m.c) {
        ASSERT_EQ(w.get<C>(e)->v, *m.c);
      }
      ASSERT_EQ(w.has<Tag>(e), m.tag);
    }
    for (Entity e : dead) ASSERT_FALSE(w.alive(e));
    std::size_t with_a = 0, with_ac = 0;
    for (auto& [bits, em] : model) {
      with_a += em.second.a.has_value();
      with_ac += em.second.a.has_value() && em.second.c.has_value() && !em.second.tag;
    }
    auto qa = w.query<const A>();
    qa.prepare();
    ASSERT_EQ(qa.entity_count(), with_a);
    auto qac = w.query<const A, const C>().without<Tag>();
    qac.prepare();
    ASSERT_EQ(qac.entity_count(), with_ac);
  };

  for (int step = 0; step < 20000; ++step) {
    const int op = std::uniform_int_distribution<int>(0, 9)(rng);
    if (model.empty() || op == 0) {
      const Entity e = w.create();
      model[e.bits()] = {e, Model{}};
      continue;
    }
    auto& [e, m] = pick();
    const int value = std::uniform_int_distribution<int>(0, 1 << 20)(rng);
    switch (op) {
      case 1:
        if (model.size() > 50) {
          ASSERT_TRUE(w.destroy(e));
          dead.push_back(e);
          model.erase(e.bits());
        }
        break;
      case 2:
        w.add(e, A{value});
        m.a = value;
        break;
      case 3:
        w.add(e, B{value * 0.5});
        m.b = value * 0.5;
        break;
      case 4:
        w.add(e, C{std::to_string(value) + " long enough to defeat SSO"});
        m.c = std::to_string(value) + " long enough to defeat SSO";
        break;
      case 5:
        w.add(e, Tag{});
        m.tag = true;
        break;
      case 6:
        ASSERT_EQ(w.remove<A>(e), m.a.has_value());
        m.a.reset();
        break;
      case 7:
        ASSERT_EQ(w.remove<C>(e), m.c.has_value());
        m.c.reset();
        break;
      case 8:
        ASSERT_EQ(w.remove<Tag>(e), m.tag);
        m.tag = false;
        break;
      case 9: {
        const Entity f = w.create_with(A{value}, C{"made whole"});
        model[f.bits()] = {f, Model{value, std::nullopt, std::string("made whole"), false}};
        break;
      }
    }
    if (step % 997 == 0) check_all();
  }
  check_all();
}

}  // namespace
}  // namespace penumbra::ecs
