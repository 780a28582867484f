// Adaptive exact predicates: [Shewchuk97] sec. 2 (expansion arithmetic) and sec. 4 (the
// floating-point filter with a dynamic error bound), written for this project.
#include "penumbra/systems/probe_cloud/exact_predicates.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace penumbra::probe_cloud {
namespace {

constexpr double kEps = 0x1p-53;  // half an ulp of 1: the unit roundoff
// Relative error bounds of the plain double evaluations below ([Shewchuk97] sec. 4, the
// "A" bounds of orient3d and insphere for the same evaluation order).
constexpr double kOrientBound = (7.0 + 56.0 * kEps) * kEps;
constexpr double kInsphereBound = (16.0 + 224.0 * kEps) * kEps;

thread_local std::uint64_t g_exact_calls = 0;

// ---- Error-free transformations ([Shewchuk97] sec. 2) ------------------------------------

inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  y = (a - av) + (bv - b);
}

inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);  // exact: the rounding error of a product is a double
}

// ---- Expansions: nonoverlapping, increasing magnitude, zeros eliminated -------------------
// A per-thread bump arena holds them; every exact evaluation resets it.

class Arena {
 public:
  struct Mark {
    std::size_t block, top;
  };
  double* alloc(std::size_t n) {
    if (!blocks_.empty() && top_ + n <= blocks_[block_].size) {
      double* p = blocks_[block_].data.get() + top_;
      top_ += n;
      return p;
    }
    return alloc_slow(n);
  }
  Mark mark() const { return {block_, top_}; }
  void release(Mark m) {
    block_ = m.block;
    top_ = m.top;
  }

 private:
  double* alloc_slow(std::size_t n) {
    if (blocks_.empty()) blocks_.push_back(make_block(n));
    if (top_ + n > blocks_[block_].size) {
      // Blocks never move, so earlier expansions stay valid; later blocks are free.
      ++block_;
      top_ = 0;
      if (block_ == blocks_.size()) {
        blocks_.push_back(make_block(n));
      } else if (blocks_[block_].size < n) {
        blocks_[block_] = make_block(n);
      }
    }
    double* p = blocks_[block_].data.get() + top_;
    top_ += n;
    return p;
  }

  struct Block {
    std::unique_ptr<double[]> data;
    std::size_t size = 0;
  };
  static Block make_block(std::size_t n) {
    const std::size_t size = std::max<std::size_t>(n, std::size_t{1} << 15);
    return {std::unique_ptr<double[]>(new double[size]), size};
  }
  std::vector<Block> blocks_;
  std::size_t block_ = 0, top_ = 0;
};

thread_local Arena g_arena;

struct Expansion {
  const double* v = nullptr;
  int n = 0;
  double estimate() const {
    double s = 0;
    for (int i = 0; i < n; ++i) s += v[i];
    return s;
  }
  int sign() const { return n == 0 ? 0 : (v[n - 1] > 0 ? 1 : (v[n - 1] < 0 ? -1 : 0)); }
};

// e + sign * f (sign = +1 or -1): merge by magnitude, then a chain of two-sums ([Shewchuk97]
// sec. 2, fast expansion sum).
Expansion add_signed(Expansion e, Expansion f, double sign) {
  const int n = e.n + f.n;
  double* h = g_arena.alloc(static_cast<std::size_t>(n));
  int i = 0, j = 0, hn = 0;
  auto next = [&] {
    if (j >= f.n || (i < e.n && std::fabs(e.v[i]) < std::fabs(f.v[j]))) return e.v[i++];
    return sign * f.v[j++];
  };
  double q = next();
  for (int k = 1; k < n; ++k) {
    double sum, err;
    two_sum(q, next(), sum, err);
    if (err != 0) h[hn++] = err;
    q = sum;
  }
  if (q != 0) h[hn++] = q;
  return {h, hn};
}

Expansion add(Expansion e, Expansion f) {
  if (e.n == 0) return f;
  if (f.n == 0) return e;
  return add_signed(e, f, 1.0);
}

// e * b ([Shewchuk97] sec. 2, scale expansion; two-product by fma).
Expansion scale(Expansion e, double b) {
  if (e.n == 0 || b == 0) return {};
  double* h = g_arena.alloc(static_cast<std::size_t>(2 * e.n));
  int hn = 0;
  double q, err;
  two_product(e.v[0], b, q, err);
  if (err != 0) h[hn++] = err;
  for (int i = 1; i < e.n; ++i) {
    double hi, lo, sum;
    two_product(e.v[i], b, hi, lo);
    two_sum(q, lo, sum, err);
    if (err != 0) h[hn++] = err;
    two_sum(hi, sum, q, err);  // |hi| >= |sum| would allow fast-two-sum; two-sum is always exact
    if (err != 0) h[hn++] = err;
  }
  if (q != 0) h[hn++] = q;
  return {h, hn};
}

Expansion mul(Expansion e, Expansion f) {
  if (e.n == 0 || f.n == 0) return {};
  if (e.n < f.n) std::swap(e, f);
  Expansion acc = scale(e, f.v[0]);
  for (int j = 1; j < f.n; ++j) acc = add(acc, scale(e, f.v[j]));
  return acc;
}

Expansion sub(Expansion e, Expansion f) {
  if (f.n == 0) return e;
  if (e.n == 0) {
    double* h = g_arena.alloc(static_cast<std::size_t>(f.n));
    for (int i = 0; i < f.n; ++i) h[i] = -f.v[i];
    return {h, f.n};
  }
  return add_signed(e, f, -1.0);
}

// a - b as an exact expansion of at most two terms.
Expansion diff(double a, double b) {
  double* h = g_arena.alloc(2);
  double x, y;
  two_diff(a, b, x, y);
  int n = 0;
  if (y != 0) h[n++] = y;
  if (x != 0) h[n++] = x;
  return {h, n};
}

struct ArenaScope {
  Arena::Mark mark = g_arena.mark();
  ~ArenaScope() { g_arena.release(mark); }
};

// 2x2 minor a_x b_y - b_x a_y of exact coordinate expansions.
Expansion minor2(Expansion ax, Expansion ay, Expansion bx, Expansion by) {
  return sub(mul(ax, by), mul(bx, ay));
}

// Exact det[a-d, b-d, c-d] (Shewchuk's orient3d order), as an expansion in the arena.
Expansion orient_exact(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                       const glm::dvec3& d) {
  const Expansion adx = diff(a.x, d.x), ady = diff(a.y, d.y), adz = diff(a.z, d.z);
  const Expansion bdx = diff(b.x, d.x), bdy = diff(b.y, d.y), bdz = diff(b.z, d.z);
  const Expansion cdx = diff(c.x, d.x), cdy = diff(c.y, d.y), cdz = diff(c.z, d.z);
  const Expansion bc = minor2(bdx, bdy, cdx, cdy);
  const Expansion ca = minor2(cdx, cdy, adx, ady);
  const Expansion ab = minor2(adx, ady, bdx, bdy);
  return add(add(mul(adz, bc), mul(bdz, ca)), mul(cdz, ab));
}

// Exact Shewchuk insphere determinant (rows [p - e, |p - e|^2] for p = a, b, c, d).
Expansion insphere_exact(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                         const glm::dvec3& d, const glm::dvec3& e) {
  const std::array<const glm::dvec3*, 4> p{&a, &b, &c, &d};
  std::array<Expansion, 4> x, y, z, lift;
  for (int i = 0; i < 4; ++i) {
    x[i] = diff(p[i]->x, e.x);
    y[i] = diff(p[i]->y, e.y);
    z[i] = diff(p[i]->z, e.z);
    lift[i] = add(add(mul(x[i], x[i]), mul(y[i], y[i])), mul(z[i], z[i]));
  }
  auto m2 = [&](int i, int j) { return minor2(x[i], y[i], x[j], y[j]); };
  const Expansion ab = m2(0, 1), bc = m2(1, 2), cd = m2(2, 3), da = m2(3, 0), ac = m2(0, 2),
                  bd = m2(1, 3);
  // 3x3 minors of (x, y, z), as in [Shewchuk97]'s insphere.
  const Expansion abc = add(sub(mul(z[0], bc), mul(z[1], ac)), mul(z[2], ab));
  const Expansion bcd = add(sub(mul(z[1], cd), mul(z[2], bd)), mul(z[3], bc));
  const Expansion cda = add(add(mul(z[2], da), mul(z[3], ac)), mul(z[0], cd));
  const Expansion dab = add(add(mul(z[3], ab), mul(z[0], bd)), mul(z[1], da));
  return add(sub(mul(lift[3], abc), mul(lift[2], dab)), sub(mul(lift[1], cda), mul(lift[0], bcd)));
}

// Plain double evaluation of Shewchuk's orient3d, det[a-d, b-d, c-d], with its error bound.
inline double orient_filter(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                            const glm::dvec3& d, double& bound) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  bound = kOrientBound * permanent;
  return det;
}

inline double insphere_filter(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                              const glm::dvec3& d, const glm::dvec3& e, double& bound) {
  const double aex = a.x - e.x, bex = b.x - e.x, cex = c.x - e.x, dex = d.x - e.x;
  const double aey = a.y - e.y, bey = b.y - e.y, cey = c.y - e.y, dey = d.y - e.y;
  const double aez = a.z - e.z, bez = b.z - e.z, cez = c.z - e.z, dez = d.z - e.z;
  const double aexbey = aex * bey, bexaey = bex * aey, ab = aexbey - bexaey;
  const double bexcey = bex * cey, cexbey = cex * bey, bc = bexcey - cexbey;
  const double cexdey = cex * dey, dexcey = dex * cey, cd = cexdey - dexcey;
  const double dexaey = dex * aey, aexdey = aex * dey, da = dexaey - aexdey;
  const double aexcey = aex * cey, cexaey = cex * aey, ac = aexcey - cexaey;
  const double bexdey = bex * dey, dexbey = dex * bey, bd = bexdey - dexbey;
  const double abc = aez * bc - bez * ac + cez * ab;
  const double bcd = bez * cd - cez * bd + dez * bc;
  const double cda = cez * da + dez * ac + aez * cd;
  const double dab = dez * ab + aez * bd + bez * da;
  const double alift = aex * aex + aey * aey + aez * aez;
  const double blift = bex * bex + bey * bey + bez * bez;
  const double clift = cex * cex + cey * cey + cez * cez;
  const double dlift = dex * dex + dey * dey + dez * dez;
  const double det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
  const double pab = std::fabs(aexbey) + std::fabs(bexaey);
  const double pbc = std::fabs(bexcey) + std::fabs(cexbey);
  const double pcd = std::fabs(cexdey) + std::fabs(dexcey);
  const double pda = std::fabs(dexaey) + std::fabs(aexdey);
  const double pac = std::fabs(aexcey) + std::fabs(cexaey);
  const double pbd = std::fabs(bexdey) + std::fabs(dexbey);
  const double paez = std::fabs(aez), pbez = std::fabs(bez), pcez = std::fabs(cez),
               pdez = std::fabs(dez);
  const double permanent = (pcd * pbez + pbd * pcez + pbc * pdez) * alift +
                           (pda * pcez + pac * pdez + pcd * paez) * blift +
                           (pab * pdez + pbd * paez + pda * pbez) * clift +
                           (pbc * paez + pac * pbez + pab * pcez) * dlift;
  bound = kInsphereBound * permanent;
  return det;
}

// ---- The common exact case: every coordinate difference is a double ----------------------
// (grids, nearby float coordinates). Same arithmetic on fixed stack buffers, no arena.

int fixed_sum(const double* e, int en, const double* f, int fn, double* h) {
  if (en == 0 || fn == 0) {
    const double* src = en == 0 ? f : e;
    const int n = en == 0 ? fn : en;
    std::copy(src, src + n, h);
    return n;
  }
  int i = 0, j = 0, hn = 0;
  auto next = [&] {
    if (j >= fn || (i < en && std::fabs(e[i]) < std::fabs(f[j]))) return e[i++];
    return f[j++];
  };
  double q = next();
  for (int k = 1; k < en + fn; ++k) {
    double sum, err;
    two_sum(q, next(), sum, err);
    if (err != 0) h[hn++] = err;
    q = sum;
  }
  if (q != 0) h[hn++] = q;
  return hn;
}

int fixed_scale(const double* e, int en, double b, double* h) {
  if (en == 0 || b == 0) return 0;
  int hn = 0;
  double q, err;
  two_product(e[0], b, q, err);
  if (err != 0) h[hn++] = err;
  for (int i = 1; i < en; ++i) {
    double hi, lo, sum;
    two_product(e[i], b, hi, lo);
    two_sum(q, lo, sum, err);
    if (err != 0) h[hn++] = err;
    two_sum(hi, sum, q, err);
    if (err != 0) h[hn++] = err;
  }
  if (q != 0) h[hn++] = q;
  return hn;
}

// a * b - c * d: at most 4 terms.
int fixed_cross(double a, double b, double c, double d, double* h) {
  double p[2], m[2];
  two_product(a, b, p[1], p[0]);
  two_product(c, d, m[1], m[0]);
  m[0] = -m[0];
  m[1] = -m[1];
  const int pn = p[0] != 0 ? 2 : (p[1] != 0 ? 1 : 0);
  const int mn = m[0] != 0 ? 2 : (m[1] != 0 ? 1 : 0);
  // Drop a zero low term so the expansions stay zero-free.
  const double* pp = p[0] != 0 ? p : p + 1;
  const double* mp = m[0] != 0 ? m : m + 1;
  return fixed_sum(pp, pn, mp, mn, h);
}

struct Fixed {
  double v[1152];
  int n = 0;
};

// x * u - y * v + z * w for short expansions u, v, w (4 terms each): at most 24 terms.
int fixed_det3(double x, const double* u, int un, double y, const double* v, int vn, double z,
               const double* w, int wn, double* h) {
  double t1[8], t2[8], t3[8], s[16];
  const int n1 = fixed_scale(u, un, x, t1);
  const int n2 = fixed_scale(v, vn, -y, t2);
  const int n3 = fixed_scale(w, wn, z, t3);
  const int ns = fixed_sum(t1, n1, t2, n2, s);
  return fixed_sum(s, ns, t3, n3, h);
}

// sign * (l0 + l1 + ...) * det: at most 2 * 6 * 24 = 288 terms.
int fixed_product(const double* l, int ln, const double* det, int dn, double sign, double* h) {
  double acc[2][288], term[48];
  int an = 0, cur = 0;
  for (int i = 0; i < ln; ++i) {
    const int tn = fixed_scale(det, dn, sign * l[i], term);
    an = fixed_sum(acc[cur], an, term, tn, acc[1 - cur]);
    cur = 1 - cur;
  }
  std::copy(acc[cur], acc[cur] + an, h);
  return an;
}

int fixed_lift(double x, double y, double z, double* h) {
  double a[2], b[2], c[2], ab[4];
  two_product(x, x, a[1], a[0]);
  two_product(y, y, b[1], b[0]);
  two_product(z, z, c[1], c[0]);
  const int an = a[0] != 0 ? 2 : (a[1] != 0 ? 1 : 0);
  const int bn = b[0] != 0 ? 2 : (b[1] != 0 ? 1 : 0);
  const int cn = c[0] != 0 ? 2 : (c[1] != 0 ? 1 : 0);
  const int abn = fixed_sum(a[0] != 0 ? a : a + 1, an, b[0] != 0 ? b : b + 1, bn, ab);
  return fixed_sum(ab, abn, c[0] != 0 ? c : c + 1, cn, h);
}

bool exact_differences(const glm::dvec3* p, int count, const glm::dvec3& origin, glm::dvec3* d) {
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      double x, y;
      two_diff(p[i][k], origin[k], x, y);
      if (y != 0) return false;
      d[i][k] = x;
    }
  }
  return true;
}

double estimate_of(const double* v, int n, int& sign) {
  sign = n == 0 ? 0 : (v[n - 1] > 0 ? 1 : -1);
  double s = 0;
  for (int i = 0; i < n; ++i) s += v[i];
  return s;
}

double orient_exact_estimate(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                             const glm::dvec3& d, int& sign) {
  ++g_exact_calls;
  const glm::dvec3 p[3] = {a, b, c};
  glm::dvec3 q[3];
  if (exact_differences(p, 3, d, q)) {
    // det[a-d, b-d, c-d] = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (...).
    double bc[4], ca[4], ab[4], det[24];
    const int nbc = fixed_cross(q[1].x, q[2].y, q[2].x, q[1].y, bc);
    const int nca = fixed_cross(q[2].x, q[0].y, q[0].x, q[2].y, ca);
    const int nab = fixed_cross(q[0].x, q[1].y, q[1].x, q[0].y, ab);
    const int n = fixed_det3(q[0].z, bc, nbc, -q[1].z, ca, nca, q[2].z, ab, nab, det);
    return estimate_of(det, n, sign);
  }
  ArenaScope scope;
  const Expansion det = orient_exact(a, b, c, d);
  sign = det.sign();
  return det.estimate();
}

double insphere_exact_estimate(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                               const glm::dvec3& d, const glm::dvec3& e, int& sign) {
  ++g_exact_calls;
  const glm::dvec3 p[4] = {a, b, c, d};
  glm::dvec3 q[4];
  if (exact_differences(p, 4, e, q)) {
    double m[6][4];  // ab, bc, cd, da, ac, bd (x, y minors)
    int mn[6];
    const int pair[6][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}, {1, 3}};
    for (int k = 0; k < 6; ++k) {
      const glm::dvec3 &u = q[pair[k][0]], &v = q[pair[k][1]];
      mn[k] = fixed_cross(u.x, v.y, v.x, u.y, m[k]);
    }
    enum { AB, BC, CD, DA, AC, BD };
    double abc[24], bcd[24], cda[24], dab[24];
    // The 3x3 minors as in [Shewchuk97]'s insphere (signs folded into the factors).
    const int nabc =
        fixed_det3(q[0].z, m[BC], mn[BC], q[1].z, m[AC], mn[AC], q[2].z, m[AB], mn[AB], abc);
    const int nbcd =
        fixed_det3(q[1].z, m[CD], mn[CD], q[2].z, m[BD], mn[BD], q[3].z, m[BC], mn[BC], bcd);
    const int ncda =
        fixed_det3(q[2].z, m[DA], mn[DA], -q[3].z, m[AC], mn[AC], q[0].z, m[CD], mn[CD], cda);
    const int ndab =
        fixed_det3(q[3].z, m[AB], mn[AB], -q[0].z, m[BD], mn[BD], q[1].z, m[DA], mn[DA], dab);
    double lift[4][6];
    int ln[4];
    for (int i = 0; i < 4; ++i) ln[i] = fixed_lift(q[i].x, q[i].y, q[i].z, lift[i]);
    // det = (dlift abc - clift dab) + (blift cda - alift bcd).
    static thread_local Fixed t[4], s[3];
    t[0].n = fixed_product(lift[3], ln[3], abc, nabc, 1.0, t[0].v);
    t[1].n = fixed_product(lift[2], ln[2], dab, ndab, -1.0, t[1].v);
    t[2].n = fixed_product(lift[1], ln[1], cda, ncda, 1.0, t[2].v);
    t[3].n = fixed_product(lift[0], ln[0], bcd, nbcd, -1.0, t[3].v);
    s[0].n = fixed_sum(t[0].v, t[0].n, t[1].v, t[1].n, s[0].v);
    s[1].n = fixed_sum(t[2].v, t[2].n, t[3].v, t[3].n, s[1].v);
    s[2].n = fixed_sum(s[0].v, s[0].n, s[1].v, s[1].n, s[2].v);
    return estimate_of(s[2].v, s[2].n, sign);
  }
  ArenaScope scope;
  const Expansion det = insphere_exact(a, b, c, d, e);
  sign = det.sign();
  return det.estimate();
}

}  // namespace

double orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                const glm::dvec3& d) {
  // Ours is det[b-a, c-a, d-a] = -det[a-d, b-d, c-d] (Shewchuk's orient3d).
  double bound;
  const double det = orient_filter(a, b, c, d, bound);
  if (det > bound || -det > bound) return -det;
  int sign;
  const double estimate = orient_exact_estimate(a, b, c, d, sign);
  if (sign == 0) return 0.0;
  // Keep the exact sign even when the estimate rounds the other way or to zero.
  const double mag = std::max(std::fabs(estimate), 0x1p-1022);
  return sign > 0 ? -mag : mag;
}

int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                  const glm::dvec3& d) {
  double bound;
  const double det = orient_filter(a, b, c, d, bound);
  if (det > bound) return -1;
  if (-det > bound) return 1;
  int sign;
  orient_exact_estimate(a, b, c, d, sign);
  return -sign;
}

double insphere(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d,
                const glm::dvec3& e) {
  // Shewchuk's insphere is > 0 inside for his orientation, the opposite of ours: negate.
  double bound;
  const double det = insphere_filter(a, b, c, d, e, bound);
  if (det > bound || -det > bound) return -det;
  int sign;
  const double estimate = insphere_exact_estimate(a, b, c, d, e, sign);
  if (sign == 0) return 0.0;
  const double mag = std::max(std::fabs(estimate), 0x1p-1022);
  return sign > 0 ? -mag : mag;
}

namespace {
int insphere_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                  const glm::dvec3& d, const glm::dvec3& e) {
  double bound;
  const double det = insphere_filter(a, b, c, d, e, bound);
  if (det > bound) return -1;
  if (-det > bound) return 1;
  int sign;
  insphere_exact_estimate(a, b, c, d, e, sign);
  return -sign;
}
}  // namespace

int insphere_perturbed(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                       const glm::dvec3& d, const glm::dvec3& e, std::uint32_t ia, std::uint32_t ib,
                       std::uint32_t ic, std::uint32_t id, std::uint32_t ie) {
  const int s = insphere_sign(a, b, c, d, e);
  if (s != 0) return s;
  // [Devillers11] (symbolic perturbation of the lifting): walk the five points from the
  // most perturbed (largest id) down; the first non-vanishing coefficient decides. The query
  // point perturbed most means "outside"; a tetrahedron vertex v perturbed most means the sign
  // of orient3d of the tetrahedron with v replaced by e.
  std::array<std::pair<std::uint32_t, int>, 5> order{{{ia, 0}, {ib, 1}, {ic, 2}, {id, 3}, {ie, 4}}};
  std::sort(order.begin(), order.end());
  for (int k = 4; k >= 0; --k) {
    int o = 0;
    switch (order[static_cast<std::size_t>(k)].second) {
      case 4:
        return -1;
      case 3:
        o = orient3d_sign(a, b, c, e);
        break;
      case 2:
        o = orient3d_sign(a, b, e, d);
        break;
      case 1:
        o = orient3d_sign(a, e, c, d);
        break;
      case 0:
        o = orient3d_sign(e, b, c, d);
        break;
    }
    if (o != 0) return o;
  }
  return -1;  // unreachable for orient3d(a, b, c, d) != 0: e's own term comes first
}

std::uint64_t exact_fallback_count() {
  return g_exact_calls;
}
void reset_exact_fallback_count() {
  g_exact_calls = 0;
}

}  // namespace penumbra::probe_cloud
