// Validation of a probe cloud (data/probe_cloud.h): run by the tests and by `./penumbra info` on
// a cloud file. Checks, with exact predicates (exact_predicates.h):
//  - sizes consistent (sh, hull_normals, transforms per cell, inner_count, bands), indices in
//    range, positions finite;
//  - every inner tetrahedron positively oriented (exact orient3d);
//  - neighbour links symmetric and sharing the right face (same three vertices);
//  - locally Delaunay: no neighbour's opposite vertex strictly inside a circumsphere (exact
//    insphere; cospherical ties allowed), which makes the whole tetrahedralization Delaunay;
//  - the union covers the hull: every hull face has exactly one outer cell, outer cells link to
//    outer cells across hull edges, the hull is convex, and the tetrahedra's volumes add up to
//    the volume the hull faces enclose (to rounding);
//  - transforms equal to probe_cell_transform() (to rounding), hull normals unit on hull probes.
// Messages name the cell and the reason; at most 20, then "... and N more".
// Threading: a pure function of an immutable cloud.
#pragma once

#include <string>
#include <vector>

#include "penumbra/data/probe_cloud.h"

namespace penumbra::probe_cloud {

struct ProbeCloudValidation {
  std::vector<std::string> errors;
  bool ok() const { return errors.empty(); }
};

ProbeCloudValidation validate_probe_cloud(const data::ProbeCloud& cloud);

}  // namespace penumbra::probe_cloud
