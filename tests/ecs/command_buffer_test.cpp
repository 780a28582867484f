#include "penumbra/ecs/command_buffer.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "penumbra/ecs/world.h"

namespace penumbra::ecs {
namespace {

struct Name {
  std::string v;
};
struct Hp {
  int v;
};

TEST(CommandBuffer, NothingHappensBeforeApply) {
  World w;
  const Entity e = w.create();
  CommandBuffer buf;
  CommandWriter cmd(buf, 0);
  const Entity p = cmd.create();
  cmd.add(p, Hp{3});
  cmd.add(e, Name{"e"});
  cmd.destroy(e);
  EXPECT_TRUE(p.is_pending());
  EXPECT_EQ(w.size(), 1u);
  EXPECT_FALSE(w.has<Name>(e));
  CommandBuffer* bufs[] = {&buf};
  const ApplyStats s = apply_commands(w, bufs);
  EXPECT_EQ(s.created, 1u);
  EXPECT_EQ(s.applied, 4u);
  EXPECT_EQ(s.dropped, 0u);
  EXPECT_FALSE(w.alive(e));
  EXPECT_EQ(w.size(), 1u);
  EXPECT_TRUE(buf.empty());
}

TEST(CommandBuffer, AppliesInKeyOrderWhicheverBufferRecorded) {
  // Two "workers" record under interleaved keys; the result must follow key order.
  auto run = [](bool swap_buffers) {
    World w;
    CommandBuffer b0(0), b1(1);
    CommandBuffer& first = swap_buffers ? b1 : b0;
    CommandBuffer& second = swap_buffers ? b0 : b1;
    CommandWriter k2(first, 2), k1(second, 1), k3(second, 3);
    const Entity e2 = k2.create();
    k2.add(e2, Hp{2});
    const Entity e1 = k1.create();
    k1.add(e1, Hp{1});
    const Entity e3 = k3.create();
    k3.add(e3, Hp{3});
    CommandBuffer* bufs[] = {&b0, &b1};
    apply_commands(w, bufs);
    std::vector<int> order;
    w.query<const Hp>().each([&](const Hp& h) { order.push_back(h.v); });
    return order;
  };
  EXPECT_EQ(run(false), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(run(true), (std::vector<int>{1, 2, 3}));
}

TEST(CommandBuffer, CommandsOnDeadEntitiesAreDropped) {
  World w;
  const Entity e = w.create();
  CommandBuffer buf;
  CommandWriter cmd(buf, 0);
  cmd.destroy(e);
  cmd.destroy(e);     // second destroy: dropped
  cmd.add(e, Hp{1});  // add to destroyed: dropped
  cmd.remove<Hp>(e);  // remove from destroyed: dropped
  CommandBuffer* bufs[] = {&buf};
  const ApplyStats s = apply_commands(w, bufs);
  EXPECT_EQ(s.applied, 1u);
  EXPECT_EQ(s.dropped, 3u);
}

TEST(CommandBuffer, ClearDestroysUnappliedPayloads) {
  auto shared = std::make_shared<int>(5);
  {
    World w;
    CommandBuffer buf;
    CommandWriter cmd(buf, 0);
    const Entity e = w.create();
    for (int i = 0; i < 1000; ++i) cmd.add(e, shared);  // crosses payload blocks
    EXPECT_EQ(shared.use_count(), 1001);
  }
  EXPECT_EQ(shared.use_count(), 1);
}

TEST(CommandBuffer, AppliedPayloadsAreMovedNotCopied) {
  World w;
  const Entity e = w.create();
  auto shared = std::make_shared<int>(5);
  CommandBuffer buf;
  CommandWriter(buf, 0).add(e, shared);
  CommandBuffer* bufs[] = {&buf};
  apply_commands(w, bufs);
  EXPECT_EQ(shared.use_count(), 2) << "one in the world, one here";
  w.destroy(e);
  EXPECT_EQ(shared.use_count(), 1);
}

}  // namespace
}  // namespace penumbra::ecs
