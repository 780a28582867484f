// Benchmark group "sh": cost of the SH operations at 3, 4 and 5 bands, each against a
// straightforward implementation measured in the same run:
//   eval      generated Cartesian polynomials   vs  spherical angles + std::assoc_legendre
//   batch     eval_basis_batch (SoA output)      vs  the same per-direction scalar calls
//   rotate    block-diagonal Rotation::apply     vs  a dense N^2 x N^2 matrix (per coefficient)
//   rotate_z  per-band 2x2 rotations             vs  the general rotation
//   product   generated, factored pair products  vs  a loop over the sparse Gamma tensor
//   square    generated square                   vs  the sparse loop with f = g
//   exp       HYB (OL + squares)                 vs  exp_numeric (quadrature: the exact one)
// Floor: operations counted (multiply-adds) times the scalar FMA throughput measured here.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "bench_registry.h"
#include "common/random_draws.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"

namespace {
namespace pb = penumbra::bench;
namespace sh = penumbra::sh;

constexpr int kDirs = 1000;  // not a power of two: SoA rows 4 KiB apart would alias in L1

std::vector<glm::vec3> directions() {
  std::mt19937 rng(7);
  std::normal_distribution<float> n(0, 1);
  std::vector<glm::vec3> d(kDirs);
  for (auto& v : d) v = glm::normalize(penumbra::test::draw_zyx<glm::vec3>(rng, n));
  return d;
}

template <int N>
sh::Coeffs<N> coeffs(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  sh::Coeffs<N> c;
  for (float& x : c) x = u(rng);
  return c;
}

// Straightforward evaluation from spherical angles (the textbook formula).
template <int N>
void eval_textbook(const glm::vec3& d, float* out) {
  const double theta = std::acos(d.z), phi = std::atan2(d.y, d.x);
  for (int l = 0; l < N; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int am = std::abs(m);
      const double k = std::sqrt((2 * l + 1) / (4 * std::numbers::pi) * std::tgamma(l - am + 1) /
                                 std::tgamma(l + am + 1));
      // std::assoc_legendre has no Condon-Shortley phase, like our basis.
      const double p = std::assoc_legendre(l, am, std::cos(theta));
      double v = k * p;
      if (m > 0) v *= std::sqrt(2.0) * std::cos(m * phi);
      if (m < 0) v *= std::sqrt(2.0) * std::sin(am * phi);
      out[l * (l + 1) + m] = static_cast<float>(v);
    }
  }
}

// Scalar calls writing every direction's coefficients (AoS), as a caller would keep them.
template <int N>
void BM_Eval(benchmark::State& state) {
  const auto dirs = directions();
  std::vector<float> out(N * N * kDirs);
  for (auto _ : state) {
    for (int d = 0; d < kDirs; ++d) sh::eval_basis<N>(dirs[d], out.data() + d * N * N);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kDirs);
}

template <int N>
void BM_EvalTextbook(benchmark::State& state) {
  const auto dirs = directions();
  float out[N * N];
  for (auto _ : state) {
    for (const auto& d : dirs) {
      eval_textbook<N>(d, out);
      benchmark::DoNotOptimize(out);
    }
  }
  state.SetItemsProcessed(state.iterations() * kDirs);
}

template <int N>
void BM_EvalBatch(benchmark::State& state) {
  const auto dirs = directions();
  std::vector<float> x(kDirs), y(kDirs), z(kDirs), out(N * N * kDirs);
  for (int i = 0; i < kDirs; ++i) {
    x[i] = dirs[i].x;
    y[i] = dirs[i].y;
    z[i] = dirs[i].z;
  }
  for (auto _ : state) {
    sh::eval_basis_batch<N>(x.data(), y.data(), z.data(), kDirs, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * kDirs);
}

template <int N>
void BM_Rotate(benchmark::State& state) {
  const sh::Rotation<N> r(
      glm::mat3(glm::rotate(glm::mat4(1), 0.7f, glm::normalize(glm::vec3(1, 2, 3)))));
  auto f = coeffs<N>(1);
  for (auto _ : state) {
    f = r.apply(f);
    benchmark::DoNotOptimize(f);
  }
}

template <int N>
void BM_RotateDense(benchmark::State& state) {
  const sh::Rotation<N> r(
      glm::mat3(glm::rotate(glm::mat4(1), 0.7f, glm::normalize(glm::vec3(1, 2, 3)))));
  std::vector<float> dense(N * N * N * N, 0.0f);  // the same matrix, stored densely
  for (int l = 0; l < N; ++l) {
    for (int m = -l; m <= l; ++m) {
      for (int n = -l; n <= l; ++n)
        dense[sh::index(l, m) * N * N + sh::index(l, n)] = r.band(l, m, n);
    }
  }
  auto f = coeffs<N>(1);
  for (auto _ : state) {
    sh::Coeffs<N> out;
    for (int i = 0; i < N * N; ++i) {  // each output coefficient as a full dot product
      float s = 0;
      for (int j = 0; j < N * N; ++j) s += dense[i * N * N + j] * f[j];
      out[i] = s;
    }
    f = out;
    benchmark::DoNotOptimize(f);
  }
}

template <int N>
void BM_RotationBuild(benchmark::State& state) {
  const glm::mat3 m(glm::rotate(glm::mat4(1), 0.7f, glm::normalize(glm::vec3(1, 2, 3))));
  for (auto _ : state) {
    sh::Rotation<N> r(m);
    benchmark::DoNotOptimize(&r);
  }
}

template <int N>
void BM_RotateZ(benchmark::State& state) {
  auto f = coeffs<N>(2);
  float a = 0.1f;
  for (auto _ : state) {
    f = sh::rotate_z<N>(f, a);
    a += 1e-3f;
    benchmark::DoNotOptimize(f);
  }
}

template <int N>
void BM_Product(benchmark::State& state) {
  auto f = coeffs<N>(3);
  const auto g = coeffs<N>(4);
  for (auto _ : state) {
    benchmark::DoNotOptimize(f = sh::product<N>(f, g));
    f[0] = 1;  // keep the values bounded
  }
}

template <int N>
void BM_ProductSparse(benchmark::State& state) {
  auto f = coeffs<N>(3);
  const auto g = coeffs<N>(4);
  for (auto _ : state) {
    benchmark::DoNotOptimize(f = sh::product_sparse<N>(f, g));
    f[0] = 1;
  }
}

template <int N>
void BM_Square(benchmark::State& state) {
  auto f = coeffs<N>(5);
  for (auto _ : state) {
    benchmark::DoNotOptimize(f = sh::square<N>(f));
    f[0] = 1;
  }
}

template <int N>
void BM_SquareSparse(benchmark::State& state) {
  auto f = coeffs<N>(5);
  for (auto _ : state) {
    benchmark::DoNotOptimize(f = sh::product_sparse<N>(f, f));
    f[0] = 1;
  }
}

template <int N>
sh::Coeffs<N> log_visibility_input() {
  auto f = coeffs<N>(6);
  for (float& c : f) c *= 1.5f;
  f[0] = -4;
  return f;
}

template <int N>
void BM_ExpHyb(benchmark::State& state) {
  const auto f = log_visibility_input<N>();
  for (auto _ : state) benchmark::DoNotOptimize(sh::exp_hyb<N>(f));
}

template <int N>
void BM_ExpNumeric(benchmark::State& state) {
  const auto f = log_visibility_input<N>();
  for (auto _ : state) benchmark::DoNotOptimize(sh::exp_numeric<N>(f));
}

// Single-threaded kernels: CPU time, Google Benchmark's default minimum time. Names as
// BENCHMARK() spells them ("BM_Eval<4>"): the summary looks them up so.
constexpr pb::Timing kCpu{.clock = pb::Timing::Clock::kCpu};

template <int N>
void register_bands() {
  const std::string n = "<" + std::to_string(N) + ">";
  pb::add("BM_Eval" + n, kCpu, BM_Eval<N>);
  pb::add("BM_EvalTextbook" + n, kCpu, BM_EvalTextbook<N>);
  pb::add("BM_EvalBatch" + n, kCpu, BM_EvalBatch<N>);
  pb::add("BM_Rotate" + n, kCpu, BM_Rotate<N>);
  pb::add("BM_RotateDense" + n, kCpu, BM_RotateDense<N>);
  pb::add("BM_RotationBuild" + n, kCpu, BM_RotationBuild<N>);
  pb::add("BM_RotateZ" + n, kCpu, BM_RotateZ<N>);
  pb::add("BM_Product" + n, kCpu, BM_Product<N>);
  pb::add("BM_ProductSparse" + n, kCpu, BM_ProductSparse<N>);
  pb::add("BM_Square" + n, kCpu, BM_Square<N>);
  pb::add("BM_SquareSparse" + n, kCpu, BM_SquareSparse<N>);
  pb::add("BM_ExpHyb" + n, kCpu, BM_ExpHyb<N>);
  pb::add("BM_ExpNumeric" + n, kCpu, BM_ExpNumeric<N>);
}

void register_benchmarks() {
  register_bands<3>();
  register_bands<4>();
  register_bands<5>();
  pb::add("BM_FmaThroughput", kCpu, pb::BM_FmaThroughput);
}

template <int N>
void summarize_bands(const pb::Results& r, pb::Summary& s, double ns_per_fma) {
  const std::string b = "<" + std::to_string(N) + ">";
  const std::string tag = std::to_string(N) + " bands: ";
  auto ns = [&](const std::string& name) { return r.real_ns("BM_" + name + b); };
  auto per_dir = [&](const std::string& name) { return pb::scale(ns(name), 1.0 / kDirs); };
  s.add_vs_baseline(tag + "eval (ns/direction)", "ns", per_dir("Eval"), per_dir("EvalTextbook"),
                    pb::Goal::none(), std::nullopt,
                    "baseline: angles + std::assoc_legendre + cos/sin");
  s.add_vs_baseline(tag + "eval batch SoA", "ns", per_dir("EvalBatch"), per_dir("Eval"),
                    pb::Goal::none(), std::nullopt,
                    "8-wide vector lanes; baseline: scalar eval per direction (AoS out)");
  s.add_vs_baseline(tag + "rotate (matrix built)", "ns", ns("Rotate"), ns("RotateDense"),
                    pb::Goal::none(),
                    pb::scale(std::optional<double>(N * (4.0 * N * N - 1) / 3), ns_per_fma),
                    "baseline: dense N^2 x N^2; floor: sum (2l+1)^2 FMAs");
  s.add_vs_baseline(tag + "rotation build (IR)", "ns", ns("RotationBuild"), std::nullopt,
                    pb::Goal::none());
  s.add_vs_baseline(tag + "rotate about z", "ns", ns("RotateZ"), ns("Rotate"), pb::Goal::none(),
                    std::nullopt, "baseline: general rotation apply");
  const double terms = sh::factored_term_count<N>();
  s.add_vs_baseline(tag + "product", "ns", ns("Product"), ns("ProductSparse"),
                    N == 4 ? pb::Goal::ratio_at_least(3.0) : pb::Goal::none(),
                    pb::scale(std::optional<double>(terms), ns_per_fma),
                    "baseline: sparse Gamma loop (" + std::to_string(sh::gaunt_entry_count<N>()) +
                        " entries); floor: " + std::to_string(static_cast<int>(terms)) + " FMAs");
  s.add_vs_baseline(tag + "square", "ns", ns("Square"), ns("SquareSparse"), pb::Goal::none(),
                    pb::scale(std::optional<double>(terms), ns_per_fma),
                    "baseline: sparse loop, f = g");
  s.add_vs_baseline(tag + "exp HYB", "ns", ns("ExpHyb"), ns("ExpNumeric"), pb::Goal::none(),
                    std::nullopt, "baseline: exp_numeric (quadrature projection)");
}

pb::Summary summarize(const pb::Results& r) {
  pb::Summary s;
  const auto fma = pb::scale(r.real_ns("BM_FmaThroughput"), 1.0 / 8192);
  const double ns_per_fma = fma.value_or(0.0);
  summarize_bands<3>(r, s, ns_per_fma);
  summarize_bands<4>(r, s, ns_per_fma);
  summarize_bands<5>(r, s, ns_per_fma);
  pb::Row row;
  row.name = "scalar FMA throughput (floor unit)";
  row.unit = "ns/FMA";
  row.value = fma;
  row.note = "8 independent chains; floors = counted multiply-adds x this";
  s.add(row);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  return pb::run_group(argc, argv, "sh", register_benchmarks, summarize);
}
