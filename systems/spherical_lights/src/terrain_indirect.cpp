#include "penumbra/systems/spherical_lights/terrain_indirect.h"

#include <algorithm>

#include <tbb/parallel_for.h>

namespace penumbra::spherical_lights {

template <int N>
std::size_t update_terrain_indirect(const blocker_accumulation::TerrainReceivers& t,
                                    const SphereLightGather<N>& gather, float min_sin,
                                    std::vector<glm::vec3>& indirect, int phase, int period) {
  const data::HeightField& f = *t.field;
  const std::size_t size = static_cast<std::size_t>(f.width) * f.height;
  if (indirect.size() != size) indirect.assign(size, glm::vec3(0.0f));
  if (!t.normals || t.normals->size() != size) return 0;
  // Per row, the span of texels some light reaches ([x0, x1), empty when x0 >= x1).
  std::vector<int> row_x0(f.height, f.width), row_x1(f.height, 0);
  for (const SphereLightSource<N>& l : gather.lights()) {
    const terrain_shadow::TexelRect r =
        blocker_accumulation::reached_texels(t, {l.centre, l.radius}, min_sin);
    for (int y = r.y0; y < r.y1; ++y) {
      row_x0[y] = std::min(row_x0[y], r.x0);
      row_x1[y] = std::max(row_x1[y], r.x1);
    }
  }
  period = std::max(period, 1);
  std::size_t reached = 0;
  for (int y = 0; y < f.height; ++y) reached += std::max(0, row_x1[y] - row_x0[y]);
  tbb::parallel_for(0, f.height, [&](int y) {
    glm::vec3* row = indirect.data() + static_cast<std::size_t>(y) * f.width;
    const int x0 = row_x0[y], x1 = row_x1[y];
    // Texels out of reach: zero now (a light that left does not linger).
    for (int x = 0; x < f.width; ++x) {
      if (x < x0 || x >= x1) row[x] = glm::vec3(0.0f);
    }
    if (x0 >= x1 || y % period != phase % period) return;
    for (int x = x0; x < x1; ++x) {
      const glm::vec3 p =
          t.origin + glm::vec3(static_cast<float>(x) * f.cell_size,
                               static_cast<float>(y) * f.cell_size, t.height_scale * f.at(x, y));
      row[x] = gather.irradiance(p, (*t.normals)[static_cast<std::size_t>(y) * f.width + x]);
    }
  });
  return reached;
}

template std::size_t update_terrain_indirect<3>(const blocker_accumulation::TerrainReceivers&,
                                                const SphereLightGather<3>&, float,
                                                std::vector<glm::vec3>&, int, int);
template std::size_t update_terrain_indirect<4>(const blocker_accumulation::TerrainReceivers&,
                                                const SphereLightGather<4>&, float,
                                                std::vector<glm::vec3>&, int, int);

}  // namespace penumbra::spherical_lights
