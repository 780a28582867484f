// The line sweep's lane kernels compiled again for AVX-512 (x86-64-v4 subsets): the same source
// and floats, in namespace detail::avx512; sweep_lanes.cpp chooses between the copies at run
// time (sweep_isa()). The target pragma covers the intrinsics and the always-inlined 8-lane
// helpers (so that blends and compares become mask-register operations) and the kernels; the
// headers with out-of-line inline functions (std::, TBB, sweep_geometry.h) come first, compiled for
// the baseline, so that every copy the linker may keep runs on any x86-64-v3 CPU.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include <tbb/parallel_for.h>

#include "sweep_geometry.h"
#include "sweep_lanes.h"

#ifdef __AVX2__
#include "avx512_target_begin.h"  // to avx512_target_end.h below

#include <immintrin.h>

#include "fast_math.h"
#include "lanes.h"

#define PENUMBRA_SWEEP_LANES_AVX512
#include "sweep_lanes.cpp"  // one source, two targets

#include "avx512_target_end.h"
#endif
