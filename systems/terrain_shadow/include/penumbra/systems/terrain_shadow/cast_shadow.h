// The height field's shadow cast onto a point above it, e.g. a sample of a dynamic object
// ([Giraud] sec. 4.1, "Height Field Cast Shadows"): the point is projected
// onto the height field's plane and the horizon along each azimuth is measured from the
// point's own height (ray_horizon, unclamped: the terrain may lie wholly below the point).
// The wedges over those horizons give its visibility on the whole sphere, in log-SH (to add
// to blockers' log-visibility before one exponentiation, [Giraud] eq. 18-23) or primal SH.
//
// A point outside the field's footprint sees only the terrain in front of it along each
// azimuth; a point below the surface sees the surrounding terrain rise steeply and is (almost)
// fully occluded: finite, documented results. Throws std::invalid_argument for a non-finite
// point or when the field is rejected by validate_horizon_input.
// Threading: pure functions of their arguments (the tables are immutable).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/height_field.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/log_wedge.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"

namespace penumbra::terrain_shadow {

// n_phi horizon elevations seen from `point` (metres, relative to sample (0, 0) at height 0).
std::vector<float> point_horizons(const data::HeightField& field, float height_scale,
                                  const glm::vec3& point, int azimuths);

// Log-SH visibility of the terrain from `point`; the table's azimuth count is used.
template <int N>
sh::Coeffs<N> cast_shadow_log_visibility(const data::HeightField& field, float height_scale,
                                         const glm::vec3& point, const LogWedge<N>& wedges);

// Primal SH visibility from `point` (a kSphere table).
template <int N>
sh::Coeffs<N> cast_shadow_visibility(const data::HeightField& field, float height_scale,
                                     const glm::vec3& point, const WedgeTable<N>& sphere);

}  // namespace penumbra::terrain_shadow
