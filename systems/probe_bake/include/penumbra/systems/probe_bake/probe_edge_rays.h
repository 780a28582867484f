// Edge rays ([Sukys14] sec. 3.2.2, "Raytracing along the edges"): light leaks through geometry
// that a Delaunay edge crosses, because the tetrahedra sharing that edge interpolate between
// probes on its two sides. So, after any placement method (and validity), the probes are
// tetrahedralized and a ray is cast along every edge both ways (a -> b and b -> a, so a thick
// wall gets a probe on each of its faces); where a ray hits a surface, a new probe is put in
// front of the hit, offset along the surface normal (the side the ray came from). Then the set is
// tetrahedralized again and the new edges are tested, up to `max_iterations` rounds.
// Rules against dense clusters ([Sukys14] sec. 3.2.2, "Oversampling", fig. 14):
//  - a hit at grazing incidence (|cos| below grazing_cos: the edge runs along a surface) adds
//    nothing;
//  - the hit must be at least min_fraction of the edge's length from the ray's origin (an
//    edge-length-relative threshold, as the thesis asks: a fixed one fails on short edges); the
//    thesis tests both vertices, but a hit near the far vertex is on that vertex's far side when
//    the wall is thick (the probe goes on the origin's side), and in the room the leaking edges
//    are long hull edges from a probe just past the inner wall: rejecting them kept every leak;
//  - the new probe sits offset_fraction of the edge length in front of the surface, never more
//    than half-way back to the ray's origin;
//  - it is dropped if inside a solid, if the offset segment itself hits geometry, or if it lies
//    within min_separation of the edge length of a probe or of an earlier new probe.
// Deterministic: edges in sorted (a, b) order, the candidates in that order.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/reference/scene.h"
#include "penumbra/systems/probe_bake/bake_scene.h"

namespace penumbra::probe_bake {

struct EdgeRaySettings {
  bool enabled = false;
  int max_iterations = 3;        // rounds of tetrahedralize -> rays -> insert
  float min_fraction = 0.2f;     // of the edge length: hit this far from both vertices
  float offset_fraction = 0.1f;  // of the edge length: the new probe in front of the surface
  float min_separation = 0.2f;   // of the edge length: no new probe this close to another
  float grazing_cos = 0.05f;     // |cos(ray, normal)| below this: along a surface, ignored
};

struct EdgeRayStats {
  std::size_t edges = 0;  // unique Delaunay edges tested (each with two rays)
  std::size_t hits = 0;   // rays that hit geometry inside the edge
  std::size_t grazing = 0, near_vertex = 0, blocked = 0, crowded = 0;  // hits dropped, by rule
  std::size_t added = 0;                                               // new probes
};

// One round: the new probe positions for the edges of the Delaunay tetrahedralization of
// `positions` (duplicates within 1 mm merged first). Adds to *stats.
std::vector<glm::vec3> edge_ray_points(const BakeScene& scene, const reference::Scene& traced,
                                       std::span<const glm::vec3> positions,
                                       const EdgeRaySettings& settings,
                                       EdgeRayStats* stats = nullptr);

}  // namespace penumbra::probe_bake
