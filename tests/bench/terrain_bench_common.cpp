// The terrain group's shared pieces (terrain_bench_common.h).
#include "terrain_bench_common.h"

#include <algorithm>
#include <cmath>

#include "penumbra/systems/terrain_shadow/transfer.h"

namespace penumbra::terrain_bench {

double wedge_ops(int n) {
  return 5.0 * n * n;
}

double transfer_ops(int n) {
  return n == 3   ? transfer_ops<3>()
         : n == 4 ? transfer_ops<4>()
         : n == 5 ? transfer_ops<5>()
                  : transfer_ops<6>();
}

double exact_transfer_ops(int n, int n_phi) {
  const int terms = n == 3   ? ts::exact_transfer_term_count<3>()
                    : n == 4 ? ts::exact_transfer_term_count<4>()
                    : n == 5 ? ts::exact_transfer_term_count<5>()
                             : ts::exact_transfer_term_count<6>();
  return n_phi * (2 + kAtanOps + 1 + wedge_ops(n + 1)) + terms + 3.0 * n * n;
}

int march_samples_to(double dl, int levels, int level_step) {
  const double sr = std::exp2(1.0 / level_step);
  double d = 1, spacing = 1;
  int k = 0;
  for (int i = 0; i < levels; ++i, d += spacing, spacing *= sr)
    if (d <= dl) ++k;
  return std::min(k, levels - 1) + 1;
}

int march_samples_all(int levels) {
  return levels;
}

int pyramid_levels(int size, int level_step) {
  return static_cast<int>(std::ceil(level_step * std::log2(static_cast<double>(size)) - 1e-9)) + 1;
}

void set_work(benchmark::State& state, double ops, double bytes) {
  state.counters["ops"] = ops;
  state.counters["bytes"] = bytes;
}

ts::HorizonParams env_horizon_params(int n_phi) {
  ts::HorizonParams p;
  p.azimuths = n_phi;
  p.height_scale = tbr::kHeightScale;
  p.clamp_at_zero = true;
  return p;
}

std::shared_ptr<const data::HeightField> scene_field(int size) {
  static std::map<int, std::shared_ptr<const data::HeightField>> cache;
  auto& f = cache[size];
  if (!f) f = tbr::load_scene(tbr::kSceneName, size);
  return f;
}

std::map<std::string, tbr::ErrorSummary>& errors() {
  static std::map<std::string, tbr::ErrorSummary> e;
  return e;
}

std::vector<CaseInfo>& cases() {
  static std::vector<CaseInfo> c;
  return c;
}

void register_case(const std::string& key, const std::string& title, const std::string& method,
                   const std::string& params_json, int size, std::optional<double> goal) {
  CaseInfo c;
  c.key = key;
  c.title = title;
  c.kind = "case";
  c.method = method;
  c.params_json = params_json;
  c.size = size;
  c.goal_ms = goal;
  cases().push_back(c);
}

}  // namespace penumbra::terrain_bench
