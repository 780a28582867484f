// The radial sweep's lane kernel compiled again for AVX-512 (x86-64-v4 subsets), as
// sweep_lanes_avx512.cpp does for the line sweep: one source (radial_sweep_lanes.cpp), two
// groups' walk on sixteen lanes with mask registers, a fourth hull point and paired links, in
// namespace detail::avx512; sweep_radial_group_lanes and sweep_radial_pair_lanes choose between
// the copies at run time (sweep_isa()). The headers
// with out-of-line inline functions come first, compiled for the baseline.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "radial_sweep_lanes.h"
#include "sweep_lanes.h"

#ifdef __AVX2__
#include "avx512_target_begin.h"  // to avx512_target_end.h below

#include <immintrin.h>

#define PENUMBRA_RADIAL_LANES_AVX512
#include "radial_sweep_lanes.cpp"  // one source, two targets

#include "avx512_target_end.h"
#endif
