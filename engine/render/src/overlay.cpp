#include "penumbra/render/overlay.h"

#include <cstdio>

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
void check_imgui(VkResult r) {
  if (r != VK_SUCCESS) std::fprintf(stderr, "imgui vulkan: %s\n", VulkanError::result_name(r));
}
}  // namespace

Overlay::Overlay(Device& device, Window& window) : device_(&device) {
  init(&window);
}

Overlay::Overlay(Device& device, VkExtent2D size) : device_(&device), size_(size) {
  init(nullptr);
}

void Overlay::init(Window* window) {
  Device& device = *device_;
  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4}};
  VkDescriptorPoolCreateInfo pool =
      vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool.maxSets = 4;
  pool.poolSizeCount = 1;
  pool.pPoolSizes = sizes;
  VkDescriptorPool p = VK_NULL_HANDLE;
  vk_check(vkCreateDescriptorPool(device.handle(), &pool, nullptr, &p), "vkCreateDescriptorPool");
  pool_ = Unique<VkDescriptorPool>(device, p, vkDestroyDescriptorPool, ObjectKind::kDescriptorPool);

  VkAttachmentDescription attachment{};
  attachment.format = FrameImages::kLdrFormat;
  attachment.samples = VK_SAMPLE_COUNT_1_BIT;
  attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachment.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  attachment.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &ref;
  VkRenderPassCreateInfo rp =
      vk_struct<VkRenderPassCreateInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO);
  rp.attachmentCount = 1;
  rp.pAttachments = &attachment;
  rp.subpassCount = 1;
  rp.pSubpasses = &subpass;
  VkRenderPass r = VK_NULL_HANDLE;
  vk_check(vkCreateRenderPass(device.handle(), &rp, nullptr, &r), "vkCreateRenderPass");
  render_pass_ = Unique<VkRenderPass>(device, r, vkDestroyRenderPass, ObjectKind::kRenderPass);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the binary
  ImGui::StyleColorsDark();
  if (window) {
    ImGui_ImplGlfw_InitForVulkan(window->glfw(), true);
    glfw_ = true;
  }
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = device.instance().handle();
  info.PhysicalDevice = device.physical();
  info.Device = device.handle();
  info.QueueFamily = device.queue_family();
  info.Queue = device.queue();
  info.DescriptorPool = pool_.get();
  info.MinImageCount = 2;
  info.ImageCount = 3;  // vertex buffers rotate over 3 frames: more than the 2 in flight
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = check_imgui;
  ImGui_ImplVulkan_Init(&info, render_pass_.get());
  device.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

Overlay::~Overlay() {
  vkDeviceWaitIdle(device_->handle());
  ImGui_ImplVulkan_Shutdown();
  if (glfw_) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Overlay::build(OverlayStats& stats, ViewSettings& view) {
  ImGui_ImplVulkan_NewFrame();
  if (glfw_) {
    ImGui_ImplGlfw_NewFrame();
  } else {
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(size_.width), static_cast<float>(size_.height));
    io.DeltaTime = 1.0f / 30.0f;
  }
  ImGui::NewFrame();
  if (!stats.hud.empty()) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(ImVec2(vp->WorkPos.x + 0.5f * vp->WorkSize.x, vp->WorkPos.y + 8),
                            ImGuiCond_Always, ImVec2(0.5f, 0.0f));
    ImGui::SetNextWindowBgAlpha(0.55f);
    ImGui::Begin("hud", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                     ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoSavedSettings);
    for (const std::string& line : stats.hud) ImGui::TextUnformatted(line.c_str());
    ImGui::End();
  }
  if (!stats.panel) {
    ImGui::Render();
    built_ = true;
    return;
  }
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  ImGui::Begin("penumbra", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s", stats.device.c_str());
  ImGui::Text("frame %.2f ms (%.0f fps)", stats.frame_ms,
              stats.frame_ms > 0 ? 1000.0 / stats.frame_ms : 0.0);
  for (const std::string& line : stats.lines) ImGui::Text("%s", line.c_str());
  if (ImGui::CollapsingHeader("CPU systems (on, ms, items done / skipped)",
                              ImGuiTreeNodeFlags_DefaultOpen)) {
    for (OverlaySystem& s : stats.systems) {
      if (s.pausable) {
        bool on = !s.paused;
        ImGui::PushID(s.name.c_str());
        if (ImGui::Checkbox("##on", &on)) s.paused = !on;
        ImGui::PopID();
        ImGui::SameLine();
      }
      if (s.reported)
        ImGui::Text("%-26s %7.3f %7llu / %-7llu", s.name.c_str(), s.ms,
                    static_cast<unsigned long long>(s.done),
                    static_cast<unsigned long long>(s.skipped));
      else
        ImGui::Text("%-26s %7.3f", s.name.c_str(), s.ms);
    }
  }
  if (ImGui::CollapsingHeader("GPU passes (ms)", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (const PassTime& p : stats.passes) ImGui::Text("%-14s %7.3f", p.name, p.ms);
  }
  if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("sky", &view.sky);
    ImGui::SameLine();
    ImGui::Checkbox("terrain", &view.terrain);
    ImGui::SameLine();
    ImGui::Checkbox("meshes", &view.meshes);
    ImGui::SameLine();
    ImGui::Checkbox("debug", &view.debug);
    ImGui::Checkbox("lighting only", &view.lighting_only);
    bool linear = view.tonemap == ViewSettings::Tonemap::kLinear;
    ImGui::SameLine();
    if (ImGui::Checkbox("linear tonemap", &linear))
      view.tonemap = linear ? ViewSettings::Tonemap::kLinear : ViewSettings::Tonemap::kFilmic;
    ImGui::SliderFloat("exposure (EV)", &view.exposure_ev, -8.0f, 8.0f, "%.1f");
    ImGui::SliderFloat("point size", &view.point_size, 1.0f, 8.0f, "%.0f");
  }
  ImGui::End();
  ImGui::Render();
  built_ = true;
}

void Overlay::record(VkCommandBuffer cmd, const FrameImages& images) {
  if (!built_) return;
  built_ = false;
  if (framebuffer_generation_ != images.generation) {
    VkImageView view = images.ldr.view.get();
    VkFramebufferCreateInfo fb =
        vk_struct<VkFramebufferCreateInfo>(VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO);
    fb.renderPass = render_pass_.get();
    fb.attachmentCount = 1;
    fb.pAttachments = &view;
    fb.width = images.extent.width;
    fb.height = images.extent.height;
    fb.layers = 1;
    VkFramebuffer f = VK_NULL_HANDLE;
    vk_check(vkCreateFramebuffer(device_->handle(), &fb, nullptr, &f), "vkCreateFramebuffer");
    framebuffer_ =
        Unique<VkFramebuffer>(*device_, f, vkDestroyFramebuffer, ObjectKind::kFramebuffer);
    framebuffer_generation_ = images.generation;
  }
  VkRenderPassBeginInfo begin =
      vk_struct<VkRenderPassBeginInfo>(VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO);
  begin.renderPass = render_pass_.get();
  begin.framebuffer = framebuffer_.get();
  begin.renderArea = {{0, 0}, images.extent};
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  vkCmdEndRenderPass(cmd);
}

}  // namespace penumbra::render
