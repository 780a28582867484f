// Compiles the code between this include and avx512_target_end.h's for x86-64-v4's AVX-512
// subsets: the dispatched kernels only (sweep_lanes_avx512.cpp, radial_sweep_lanes_avx512.cpp,
// radial_lookup_avx512.cpp, cap_transfer_lanes_avx512.cpp, wedge_sum_avx512.cpp; chosen at run
// time by sweep_isa()). Headers whose inline functions other objects may share must come before
// it (tests/terrain_shadow/check_isa_isolation.py checks). No include guard: one pair per use.
#ifdef __clang__  // clang has no GCC target pragma; its attribute pragma does the same here
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512bw,avx512dq"))), \
                             apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq")
#endif
