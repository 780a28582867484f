// What 512-bit gathers and scatters cost on this CPU: the bound that ruled out a horizon walk with
// each lane at its own step (docs/terrain_shadow_log.md, "Nineteenth round"). Not a Google
// Benchmark group: a plain loop per operation, 10^7 iterations, addresses spread over 64 KiB as the
// sweep's links are; prints ns per iteration. Built only for x86-64 (compiled for AVX-512); run it
// on a CPU with AVX-512 (it says so and exits otherwise), pinned to one core:
//   taskset -c 1 build/release/tests/bench/gather_scatter_cost
#include <immintrin.h>

#include <chrono>
#include <cstdio>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kIterations = 10'000'000;
constexpr __mmask16 kAll =
    0xffff;  // mask forms: GCC 12 warns on the unmasked ones' undefined source

template <class Body>
double ns_per_iteration(int iterations, Body body) {
  const auto t0 = Clock::now();
  for (int i = 0; i < iterations; ++i) body();
  return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / iterations;
}

}  // namespace

int main() {
  if (!__builtin_cpu_supports("avx512f")) {
    std::puts("gather_scatter_cost: this CPU has no AVX-512");
    return 1;
  }
  std::vector<float> source(1 << 16, 1.0f), links(1 << 16, 1.0f);
  std::vector<int> chain(1 << 16);
  for (std::size_t i = 0; i < chain.size(); ++i)
    chain[i] = static_cast<int>((i * 7919 + 16) & 0xfff0);
  float* p = source.data();
  float* q = links.data();
  __m512i idx =
      _mm512_setr_epi32(0, 37, 90, 151, 203, 260, 333, 390, 455, 512, 577, 640, 701, 777, 830, 901);
  const __m512i step = _mm512_set1_epi32(16), wrap = _mm512_set1_epi32(0x3fff);
  const __m512 value = _mm512_set1_ps(2.0f);
  __m512 sum = _mm512_setzero_ps();
  auto next = [&] { idx = _mm512_and_si512(_mm512_add_epi32(idx, step), wrap); };

  const double gather16 = ns_per_iteration(kIterations, [&] {
    next();
    sum = _mm512_add_ps(sum, _mm512_mask_i32gather_ps(_mm512_setzero_ps(), kAll, idx, p, 4));
  });
  const double scatter16 = ns_per_iteration(kIterations, [&] {
    next();
    _mm512_i32scatter_ps(q, idx, value, 4);
  });
  auto scatter_pairs = [&] {  // a link's height and j as one 64-bit element, 16 lanes
    _mm512_i32scatter_epi64(q, _mm512_maskz_extracti32x8_epi32(0xff, idx, 0),
                            _mm512_castps_si512(value), 8);
    _mm512_i32scatter_epi64(q, _mm512_maskz_extracti32x8_epi32(0xff, idx, 1),
                            _mm512_castps_si512(value), 8);
  };
  const double scatter_8x2 = ns_per_iteration(kIterations, [&] {
    next();
    scatter_pairs();
  });
  const double gather_and_scatters = ns_per_iteration(kIterations, [&] {
    next();
    sum = _mm512_add_ps(sum, _mm512_mask_i32gather_ps(_mm512_setzero_ps(), kAll, idx, p, 4));
    scatter_pairs();
  });
  const double gather_8x64 = ns_per_iteration(kIterations, [&] {
    next();
    sum = _mm512_add_ps(sum, _mm512_castsi512_ps(_mm512_mask_i32gather_epi64(
                                 _mm512_setzero_si512(), 0xff,
                                 _mm512_maskz_extracti32x8_epi32(0xff, idx, 0), p, 8)));
  });
  __m512i at = _mm512_setzero_si512();  // each gather's addresses from the last one's values
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const double latency = ns_per_iteration(kIterations / 4, [&] {
    at = _mm512_add_epi32(
        _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), kAll, at, chain.data(), 4), lane);
  });

  std::printf("gather of 16 floats                 %.2f ns\n", gather16);
  std::printf("scatter of 16 floats                %.2f ns\n", scatter16);
  std::printf("two scatters of 8 64-bit elements   %.2f ns\n", scatter_8x2);
  std::printf("the gather and the two scatters     %.2f ns\n", gather_and_scatters);
  std::printf("gather of 8 64-bit elements         %.2f ns\n", gather_8x64);
  std::printf("a gather's latency (dependent)      %.2f ns\n", latency);
  alignas(64) float sums[16];
  alignas(64) int ats[16];
  _mm512_store_ps(sums, sum);
  _mm512_store_si512(ats, at);
  std::printf("(checksums %g %d)\n", sums[0], ats[0]);
  return 0;
}
