// Offline sphere-set fitting for the blocker accumulation system: N spheres that bound a
// triangle mesh (./penumbra spheres, engine/assets/tools/penumbra_spheres.cpp). The measured
// figures are in docs/blocker_accumulation.md, "Fitting sphere sets".
//
// Samples (deterministic for a seed, whatever the thread count):
// - surface: `surface_samples` area-weighted uniform points on the triangles, plus every vertex
//   a triangle uses;
// - volume: the bounding box cut into about `volume_cells` voxels, one jittered point per voxel,
//   kept when inside. Inside is ray parity against the triangles along +x, +y and +z (an odd
//   crossing count is a vote, two votes of three are inside), so a few holes (Suzanne has 160
//   open edges) do not spoil it.
// The fitting points are the surface and the inside volume samples, all weighted alike.
// Methods; in both each sphere bounds its fitting points, so the union bounds them all:
// - kKMeans ([Giraud] sec. 4.2 says only "a simple k-means clustering"; this is ours): k-means++
//   seeding (Arthur and Vassilvitskii 2007), then Lloyd iterations (nearest centre, centre the
//   members' mean) until no point changes cluster, at most 100; an empty cluster restarts at the
//   point farthest from its centre. Each radius is the largest member distance.
// - kVariational ([Guerrero08] sec. 4.1 eq. 1, after Wang et al. 2006, whose own rules are not
//   in our sources): minimises T = sum_i V(S_i \ O), the per-sphere outside volumes summed, with
//   V(S \ O) = 4/3 pi r^3 - (voxel volume) x (inside voxel centres in S). From the k-means set
//   it alternates, Lloyd-style: assignment, each fitting point to the sphere of least
//   [Guerrero08] eq. 2 distance |p - c| / r (always a sphere that covers it: its own gives
//   d <= 1); update, per sphere the centre of least outside volume with the radius its largest
//   member distance (compass search over 14 directions from the better of the old centre and
//   the members' mean). Giving points away and re-minimising never raises a sphere's cost, so T
//   only falls (up to the voxel count's granularity). A sphere left with no point splits the
//   sphere of largest outside volume (2-means of its members). Stops when T falls by less than
//   1e-4 relative or after `max_iterations`; returns the set of least T seen, never worse than
//   the k-means start. Volume samples are fitted too, not only the surface: the union then
//   bounds the solid, not only its skin, and Er measures outside volume, not interior voids.
// Closing (both methods): every triangle, split at its longest edge until no edge exceeds 1/50
// of the box diagonal, must lie in the union, checked piecewise: a piece lies in a sphere when
// its three corners do (spheres are convex); a piece no single sphere holds is split again, down
// to edges of 1/1000 of the diagonal, where the sphere needing the least growth grows to hold
// it. So the union bounds the whole surface, not only the samples it was fitted to
// (grown_spheres counts the spheres grown). Centres are rounded to float first, and radii rounded
// up by a relative 1e-6 plus 1e-7 of the diagonal. Spheres are roots (parent -1).
// Figures: Er = vol(union) / vol(mesh) - 1, both volumes from one Monte Carlo estimate:
// `eval_samples` jittered stratified points in the box bounding mesh and spheres, each tested
// against the mesh (the same ray parity) and the union. Coverage: the fraction of
// `coverage_samples` fresh area-weighted surface points (not the fitting ones) inside a sphere,
// within 1e-6 of the diagonal; 1 after closing, up to that tolerance.
// Errors: FitError naming the mesh and the reason: no triangles, a non-finite position, a flat
// mesh (box thinner than 1e-6 of its diagonal), a surface enclosing no volume (fewer than 8
// inside voxels, or a generalized winding number (Jacobson et al. 2013) below 1/2 at more than
// half of up to 256 points parity calls inside: a single triangle, an open sheet), or a sphere
// count below 1, above kMaxFitSpheres or above the number of fitting points.
// Threading: uses oneTBB's current arena; independent calls may run concurrently. `progress` is
// called on the calling thread only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "penumbra/assets/gltf.h"
#include "penumbra/assets/sphere_file.h"
#include "penumbra/data/mesh.h"
#include "penumbra/data/sphere_set.h"

namespace penumbra::assets {

inline constexpr int kMaxFitSpheres = 1024;

class FitError : public std::runtime_error {
 public:
  FitError(std::string mesh, std::string reason)
      : std::runtime_error(mesh + ": " + reason),
        mesh_(std::move(mesh)),
        reason_(std::move(reason)) {}
  const std::string& mesh() const { return mesh_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string mesh_;
  std::string reason_;
};

struct SphereFitOptions {
  int count = 64;
  SphereFitMethod method = SphereFitMethod::kVariational;
  int surface_samples = 16384;     // area-weighted fitting samples (vertices come on top)
  int volume_cells = 65536;        // voxels over the bounding box (inside ones: volume samples)
  int max_iterations = 40;         // variational iterations after the k-means start
  int eval_samples = 1 << 18;      // Monte Carlo points for Er
  int coverage_samples = 1 << 16;  // fresh surface points for the coverage
  std::uint64_t seed = 1;
  // fraction done in [0, 1] and the stage ("sampling", "kmeans", "variational", "evaluating").
  std::function<void(double, std::string_view)> progress;
};

// Er and coverage of a sphere set against a mesh (the figures above).
struct SphereSetError {
  double outside_volume_ratio = 0;  // Er = union_volume / mesh_volume - 1
  double coverage = 0;              // of the surface
  double volume_coverage = 0;       // fraction of the mesh volume inside the union
  double mesh_volume = 0;           // Monte Carlo, model units^3
  double union_volume = 0;
  std::size_t eval_samples = 0;
  std::size_t coverage_samples = 0;
};

struct SphereFitResult {
  std::vector<data::Sphere> spheres;
  SphereFitMethod method = SphereFitMethod::kNone;
  SphereSetError error;
  double outside_volume_sum = 0;   // [Guerrero08] eq. 1 T on the voxel grid
  int iterations = 0;              // Lloyd iterations of the method (variational: after k-means)
  std::size_t grown_spheres = 0;   // spheres grown to close the surface (see the header)
  std::size_t surface_points = 0;  // fitting points on the surface (samples + vertices)
  std::size_t volume_points = 0;   // fitting points inside
  double seconds = 0;              // wall time of fit_spheres, evaluation included
};

// Every instance of the model in one mesh, in the model's engine frame (z up: each instance's
// `world` applied, as spawn_model places the meshes under an identity root). Name: model.source.
data::MeshData merge_instances(const Model& model);

SphereFitResult fit_spheres(const data::MeshData& mesh, const SphereFitOptions& options);

// The figures of any sphere set (uses eval_samples, coverage_samples, seed of `options`).
SphereSetError evaluate_sphere_set(const data::MeshData& mesh,
                                   const std::vector<data::Sphere>& spheres,
                                   const SphereFitOptions& options = {});

// The file contents for a fit of `source_model` (a file name).
SphereSetFile to_sphere_file(const SphereFitResult& fit, std::string source_model);

}  // namespace penumbra::assets
