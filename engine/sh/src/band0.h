// Internal: the constant band-0 basis function, y_0 = 1 / sqrt(4 pi) (exp_log.cpp, batch.cpp).
#pragma once

namespace penumbra::sh::detail {

inline constexpr float kY0 = 0.28209479177387814f;

}  // namespace penumbra::sh::detail
