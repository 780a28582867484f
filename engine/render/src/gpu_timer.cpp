#include "penumbra/render/gpu_timer.h"

#include <algorithm>
#include <cstdio>
#include <ostream>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {

GpuTimer::GpuTimer(Device& device, std::uint32_t max_passes)
    : device_(&device),
      capacity_(max_passes),
      ns_per_tick_(device.properties().limits.timestampPeriod),
      isolate_(device.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
  if (!device.timestamps()) return;
  VkQueryPoolCreateInfo info =
      vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * (max_passes + 1);  // marks, then as many isolating stamps
  vk_check(vkCreateQueryPool(device.handle(), &info, nullptr, &pool_), "vkCreateQueryPool");
  device.count(ObjectKind::kQueryPool, +1);
}

GpuTimer::~GpuTimer() {
  if (pool_ == VK_NULL_HANDLE) return;
  vkDestroyQueryPool(device_->handle(), pool_, nullptr);
  device_->count(ObjectKind::kQueryPool, -1);
}

void GpuTimer::start(VkCommandBuffer cmd, bool enabled) {
  names_.clear();
  enabled_ = enabled && pool_ != VK_NULL_HANDLE;
  if (!enabled_) return;
  vkCmdResetQueryPool(cmd, pool_, 0, 2 * (capacity_ + 1));
  stamp(cmd, 0);
}

void GpuTimer::mark(VkCommandBuffer cmd, const char* name) {
  if (!enabled_ || names_.size() >= capacity_) return;
  names_.push_back(name);
  stamp(cmd, static_cast<std::uint32_t>(names_.size()));
}

void GpuTimer::stamp(VkCommandBuffer cmd, std::uint32_t index) {
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, index);
  if (isolate_)
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, capacity_ + 1 + index);
}

std::vector<PassTime> GpuTimer::read() {
  std::vector<PassTime> out;
  if (pool_ == VK_NULL_HANDLE || names_.empty()) return out;
  std::vector<std::uint64_t> ticks(names_.size() + 1);
  const VkResult r = vkGetQueryPoolResults(
      device_->handle(), pool_, 0, static_cast<std::uint32_t>(ticks.size()),
      ticks.size() * sizeof(std::uint64_t), ticks.data(), sizeof(std::uint64_t),
      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
  vk_check(r, "vkGetQueryPoolResults");
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const std::uint64_t a = ticks[i], b = ticks[i + 1];
    out.push_back({names_[i], b > a ? static_cast<double>(b - a) * ns_per_tick_ * 1e-6 : 0.0});
  }
  names_.clear();
  return out;
}

void PassTimingTable::add(std::span<const PassTime> frame) {
  if (frame.empty()) return;
  ++frames_;
  for (const PassTime& p : frame) {
    auto it =
        std::find_if(rows_.begin(), rows_.end(), [&](const Row& r) { return r.name == p.name; });
    if (it == rows_.end()) {
      rows_.push_back({p.name});
      it = rows_.end() - 1;
    }
    it->total_ms += p.ms;
    it->max_ms = std::max(it->max_ms, p.ms);
    ++it->count;
  }
}

double PassTimingTable::mean_total_ms() const {
  if (frames_ == 0) return 0;
  double t = 0;
  for (const Row& r : rows_) t += r.total_ms;
  return t / static_cast<double>(frames_);
}

double PassTimingTable::mean_ms(const std::string& name) const {
  for (const Row& r : rows_)
    if (r.name == name) return frames_ ? r.total_ms / static_cast<double>(frames_) : 0.0;
  return 0;
}

void PassTimingTable::clear() {
  rows_.clear();
  frames_ = 0;
}

void PassTimingTable::print(std::ostream& out) const {
  char line[160];
  std::snprintf(line, sizeof line, "%-16s %10s %10s %7s\n", "GPU pass", "mean ms", "max ms",
                "share");
  out << line;
  const double total = mean_total_ms();
  for (const Row& r : rows_) {
    const double mean = frames_ ? r.total_ms / static_cast<double>(frames_) : 0.0;
    std::snprintf(line, sizeof line, "%-16s %10.3f %10.3f %6.1f%%\n", r.name.c_str(), mean,
                  r.max_ms, total > 0 ? 100.0 * mean / total : 0.0);
    out << line;
  }
  std::snprintf(line, sizeof line, "%-16s %10.3f   (%zu frames)\n", "GPU frame", total, frames_);
  out << line;
}

}  // namespace penumbra::render
