#include "penumbra/render/shaders.h"

#include <gtest/gtest.h>

#include <string>

#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(Shaders, EveryShaderIsEmbeddedSpirvTheDriverAccepts) {
  test::TestContext ctx;
  for (int i = 0; i < static_cast<int>(Shader::kCount); ++i) {
    const auto s = static_cast<Shader>(i);
    const auto code = shader_spirv(s);
    ASSERT_GT(code.size(), 5u) << shader_name(s);
    EXPECT_EQ(code[0], 0x07230203u) << shader_name(s) << ": SPIR-V magic";
    EXPECT_NE(std::string(shader_name(s)).find(".glsl"), std::string::npos);
    EXPECT_TRUE(create_shader_module(ctx.device, s)) << shader_name(s);
  }
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
