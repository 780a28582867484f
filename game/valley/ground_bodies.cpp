#include "penumbra/game/ground_bodies.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/data/finite.h"
#include "penumbra/data/height_field.h"
#include "random_bits.h"

namespace penumbra::game {
namespace {

using detail::mix_bits;
using detail::unit_float;

// Relaxation passes over the contacts: a push can open another overlap; four leave at most a
// sixteenth of it in the worst chain of three.
constexpr int kContactPasses = 4;

using data::finite;

// The field's world rectangle, shrunk by `margin`.
void bounds(const components::Terrain& t, float margin, glm::vec2& lo, glm::vec2& hi) {
  const data::HeightField& f = *t.heights;
  lo = glm::vec2(t.origin) + margin;
  hi = glm::vec2(t.origin) + f.cell_size * glm::vec2(f.width - 1, f.height - 1) - margin;
  hi = glm::max(hi, lo);
}

// A roller at rest starts again from the highest of eight points drawn from its stream.
void restart_on_a_ridge(GroundBody& b, const components::Terrain& t) {
  glm::vec2 lo, hi;
  bounds(t, b.radius, lo, hi);
  std::uint32_t s = mix_bits(b.id * 0x9e3779b9U + ++b.restarts);
  float best = -1e30f;
  for (int k = 0; k < 8; ++k) {
    s = mix_bits(s + 1);
    const float u = unit_float(s);
    s = mix_bits(s + 1);
    const glm::vec2 p = lo + (hi - lo) * glm::vec2(u, unit_float(s));
    const float h = ground_height(t, p);
    if (h > best) best = h, b.position = p;
  }
  b.velocity = glm::vec2(0.0f);
  b.rest = 0.0f;
}

}  // namespace

void step_body(GroundBody& b, const components::Terrain& t, float dt, std::uint64_t step,
               const BodyConfig& c) {
  if (!finite(b.position) || !finite(b.velocity) || !std::isfinite(b.heading)) {
    b.position = finite(b.position) ? b.position : glm::vec2(t.origin);
    b.velocity = glm::vec2(0.0f);
    b.heading = 0.0f;
  }
  if (b.motion == BodyMotion::kRoll) {
    b.velocity += (-c.slope_pull * ground_slope(t, b.position) - c.roll_drag * b.velocity) * dt;
    const glm::vec2 moved = b.velocity * dt;
    b.position += moved;
    const float distance = glm::length(moved);
    if (distance > 0 && b.radius > 0) {  // rolling without slipping about the horizontal axis
      const glm::vec3 axis = glm::normalize(glm::cross(glm::vec3(0, 0, 1), glm::vec3(moved, 0)));
      b.tumble = glm::normalize(glm::angleAxis(distance / b.radius, axis) * b.tumble);
    }
    b.rest = glm::length(b.velocity) < c.rest_speed ? b.rest + dt : 0.0f;
    if (b.rest > c.rest_time && t.heights) restart_on_a_ridge(b, t);
    return;
  }
  // Wandering: a new turn rate every two seconds from the body's stream; away from climbs
  // steeper than `steep` and from the field's edge.
  const std::uint32_t period = static_cast<std::uint32_t>(step / 60);
  float turn =
      c.wander_turn * (2.0f * unit_float(mix_bits(b.id * 0x85ebca6bU ^ mix_bits(period))) - 1.0f);
  const glm::vec2 dir(std::cos(b.heading), std::sin(b.heading));
  if (glm::dot(ground_slope(t, b.position), dir) > c.steep) turn = c.wander_turn;
  if (t.heights) {
    glm::vec2 lo, hi;
    bounds(t, 4.0f * b.radius, lo, hi);
    const glm::vec2 centre = 0.5f * (lo + hi);
    if (glm::any(glm::lessThan(b.position, lo)) || glm::any(glm::greaterThan(b.position, hi))) {
      const float home = std::atan2(centre.y - b.position.y, centre.x - b.position.x);
      turn = std::remainder(home - b.heading, 2 * std::numbers::pi_v<float>) > 0 ? c.wander_turn
                                                                                 : -c.wander_turn;
    }
  }
  b.heading = std::remainder(b.heading + turn * dt, 2 * std::numbers::pi_v<float>);
  b.velocity = c.wander_speed * glm::vec2(std::cos(b.heading), std::sin(b.heading));
  b.position += b.velocity * dt;
}

void separate_bodies(std::span<GroundBody> bodies, std::span<const Obstacle> fixed,
                     const components::Terrain& t) {
  auto bounce = [](glm::vec2& v, glm::vec2 n) {  // n: out of the contact
    const float inward = glm::dot(v, n);
    if (inward < 0) v -= 1.5f * inward * n;
  };
  for (int pass = 0; pass < kContactPasses; ++pass)
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      for (std::size_t j = i + 1; j < bodies.size(); ++j) {
        GroundBody &a = bodies[i], &b = bodies[j];
        const glm::vec2 d = a.position - b.position;
        const float reach = a.radius + b.radius, dist = glm::length(d);
        if (!(dist < reach)) continue;
        const glm::vec2 n = dist > 1e-3f ? d / dist : glm::vec2(1.0f, 0.0f);
        const float push = 0.5f * (reach - dist);
        a.position += push * n;
        b.position -= push * n;
        bounce(a.velocity, n);
        bounce(b.velocity, -n);
      }
      GroundBody& a = bodies[i];
      for (const Obstacle& o : fixed) {
        const glm::vec2 d = a.position - o.centre;
        const float reach = a.radius + o.radius, dist = glm::length(d);
        if (!(dist < reach)) continue;
        const glm::vec2 n = dist > 1e-3f ? d / dist : glm::vec2(1.0f, 0.0f);
        a.position = o.centre + reach * n;
        bounce(a.velocity, n);
      }
      if (t.heights) {
        glm::vec2 lo, hi;
        bounds(t, a.radius, lo, hi);
        for (int k = 0; k < 2; ++k)
          if (a.position[k] < lo[k] || a.position[k] > hi[k]) {
            a.position[k] = std::clamp(a.position[k], lo[k], hi[k]);
            a.velocity[k] = -0.5f * a.velocity[k];
          }
      }
    }
}

glm::mat4 body_transform(const GroundBody& b, const components::Terrain& t, float scale,
                         const glm::vec3& model_centre) {
  const glm::vec3 at(b.position, ground_height(t, b.position) + b.lift);
  glm::mat4 m = glm::translate(glm::mat4(1.0f), at);
  if (b.motion == BodyMotion::kRoll) {
    m = m * glm::mat4_cast(b.tumble);
  } else {
    m = glm::rotate(m, b.heading - 0.5f * std::numbers::pi_v<float>, glm::vec3(0, 0, 1));
    m = glm::rotate(m, 0.5f * std::numbers::pi_v<float>, glm::vec3(1, 0, 0));  // glTF: y up
  }
  m = glm::scale(m, glm::vec3(scale));
  return glm::translate(m, -model_centre);
}

}  // namespace penumbra::game
