#include "core/gamut/gamut_boundary.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "core/multiversion.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

// A generator counts as lying in a facet's plane when |n . h| <= kInPlane |h|: the CIE tables'
// zbar is exactly 0 beyond ~650 nm, so many generators are coplanar to rounding; true
// off-plane generators are far above this (the smallest, zbar near 650 nm, ~1e-5).
constexpr double kInPlane = 1e-9;
// Values within this of 0 or 1 are rounding and snap to the bound.
constexpr double kSnap = 1e-12;

double snap01(double v) {
  if (v < kSnap) return 0.0;
  if (v > 1 - kSnap) return 1.0;
  return v;
}

double cross2(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

// Reduces rho (values in [0, 1] for generators g, 2-D) to at most two fractional entries
// without changing sum rho_k g_k: three fractional generators in a plane are linearly
// dependent, so moving along their null vector until one reaches a bound keeps the colour.
void reduce_fractional(std::vector<double>& rho, const std::vector<std::array<double, 2>>& g) {
  for (std::size_t guard = 0; guard <= rho.size(); ++guard) {
    std::size_t f[3], nf = 0;
    for (std::size_t k = 0; k < rho.size(); ++k) {
      rho[k] = snap01(rho[k]);
      if (rho[k] > 0 && rho[k] < 1 && nf < 3) f[nf++] = k;
    }
    if (nf < 3) return;
    const auto &g1 = g[f[0]], &g2 = g[f[1]], &g3 = g[f[2]];
    double c[3] = {cross2(g2[0], g2[1], g3[0], g3[1]), cross2(g3[0], g3[1], g1[0], g1[1]),
                   cross2(g1[0], g1[1], g2[0], g2[1])};
    const double n1 = std::hypot(g1[0], g1[1]), n2 = std::hypot(g2[0], g2[1]);
    const double n3 = std::hypot(g3[0], g3[1]);
    if (std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2]) <= 1e-15 * (n1 * n2 + n2 * n3 + n3 * n1)) {
      // All three parallel (same direction, in a pointed cone): |g2| g1 - |g1| g2 = 0.
      c[0] = n2, c[1] = -n1, c[2] = 0;
    }
    double step = INFINITY;
    for (int t = 0; t < 3; ++t) {
      const double r = rho[f[t]];
      if (c[t] > 0) step = std::min(step, (1 - r) / c[t]);
      if (c[t] < 0) step = std::min(step, r / -c[t]);
    }
    if (!std::isfinite(step)) return;
    int hit = -1;
    double best = INFINITY;
    for (int t = 0; t < 3; ++t) {
      rho[f[t]] += step * c[t];
      const double gap = std::min(rho[f[t]], 1 - rho[f[t]]);
      if (gap < best) best = gap, hit = t;
    }
    rho[f[hit]] = rho[f[hit]] < 0.5 ? 0.0 : 1.0;  // the one that reached its bound
  }
}

// The boundary spectrum from a full vector of values in [0, 1] with at most two fractional.
BoundarySpectrum pack(const std::vector<double>& rho) {
  BoundarySpectrum s;
  s.mask.assign((rho.size() + 31) / 32, 0u);
  std::size_t picked = 0;
  for (std::size_t k = 0; k < rho.size(); ++k) {
    const double v = rho[k];
    if (v == 1.0) {
      s.mask[k / 32] |= 1u << (k % 32);
    } else if (v != 0.0) {
      if (picked == 0) s.i = s.j = static_cast<std::uint32_t>(k), s.a = s.b = v;
      if (picked == 1) s.j = static_cast<std::uint32_t>(k), s.b = v;
      ++picked;
    }
  }
  if (picked == 0) s.a = s.b = rho.empty() ? 0.0 : rho[0];  // sample 0 keeps its own value
  return s;
}

}  // namespace

SolidBoundary::SolidBoundary(std::span<const Xyz> columns, const Mat3& target_from_frame) {
  if (!(std::abs(det(target_from_frame)) > 0)) throw Error("the table's frame is singular");
  const Mat3 to_frame = inverse(target_from_frame);
  for (const Xyz& c : columns) h_.push_back(mul(to_frame, c));
  for (const Xyz& h : h_)
    for (int a = 0; a < 3; ++a) {
      lower_[a] += std::min(h[a], 0.0);
      upper_[a] += std::max(h[a], 0.0);
    }
  // Every facet of a zonotope in 3-D is spanned by two generators: the normals h_i x h_j over
  // all pairs are all the facet normals; the support in direction n is the sum of the
  // positive parts of n . h_k. Planes equal to rounding (coplanar generators) are merged.
  struct Key {
    long long x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      // In unsigned arithmetic: the products wrap by definition (signed overflow is undefined).
      const auto u = [](long long v) { return static_cast<std::uint64_t>(v); };
      return static_cast<std::size_t>(u(k.x) * 73856093u ^ u(k.y) * 19349663u ^ u(k.z) * 83492791u);
    }
  };
  std::unordered_map<Key, std::size_t, KeyHash> seen;
  auto add = [&](const Xyz& n, double d) {
    const Key key{std::llround(n.X * 1e12), std::llround(n.Y * 1e12), std::llround(n.Z * 1e12)};
    auto [it, fresh] = seen.emplace(key, planes_.size());
    if (fresh)
      planes_.push_back({n, d});
    else
      planes_[it->second].d = std::max(planes_[it->second].d, d);
  };
  for (std::size_t i = 0; i < h_.size(); ++i)
    for (std::size_t j = i + 1; j < h_.size(); ++j) {
      Xyz n = cross(h_[i], h_[j]);
      const double len = std::sqrt(dot(n, n));
      const double scale = std::sqrt(dot(h_[i], h_[i]) * dot(h_[j], h_[j]));
      if (!(len > 1e-12 * scale)) continue;  // parallel generators span no facet
      n = (1.0 / len) * n;
      double pos = 0, neg = 0;
      for (const Xyz& h : h_) {
        const double v = dot(n, h);
        (v > 0 ? pos : neg) += v;
      }
      add(n, pos);
      add(Xyz{} - n, -neg);
    }
  for (const Plane& p : planes_) {
    nx_.push_back(p.n.X), ny_.push_back(p.n.Y), nz_.push_back(p.n.Z), d_.push_back(p.d);
  }
}

std::vector<Plane> SolidBoundary::cutting(const Xyz& lower, const Xyz& upper, double eps) const {
  const Xyz c = 0.5 * (lower + upper), h = 0.5 * (upper - lower);
  std::vector<Plane> out;
  const std::size_t n = d_.size();
  for (std::size_t f = 0; f < n; ++f) {
    const double support = nx_[f] * c.X + ny_[f] * c.Y + nz_[f] * c.Z + std::abs(nx_[f]) * h.X +
                           std::abs(ny_[f]) * h.Y + std::abs(nz_[f]) * h.Z;
    if (support > d_[f] + eps * std::max(lower.max_abs(), upper.max_abs()))
      out.push_back(planes_[f]);
  }
  return out;
}

// Thousands of planes per call (node classification, boundary vertices): vectorised, and
// compiled for AVX2 as well as baseline x86-64, picked at load time.
SPECTRALIZE_MULTIVERSION_V3 double SolidBoundary::distance(const Xyz& u, std::size_t* facet) const {
  const std::size_t n = d_.size();
  const double *x = nx_.data(), *y = ny_.data(), *z = nz_.data(), *d = d_.data();
  double best = -INFINITY;
#pragma omp simd reduction(max : best)
  for (std::size_t f = 0; f < n; ++f)
    best = std::max(best, x[f] * u.X + y[f] * u.Y + z[f] * u.Z - d[f]);
  if (facet) {
    *facet = 0;
    for (std::size_t f = 0; f < n; ++f)
      if (x[f] * u.X + y[f] * u.Y + z[f] * u.Z - d[f] == best) {
        *facet = f;
        break;
      }
  }
  return best;
}

double SolidBoundary::max_step(const Xyz& from, const Xyz& to) const {
  const Xyz d = to - from;
  double s = INFINITY;
  for (const Plane& p : planes_) {
    const double rate = dot(p.n, d);
    if (rate > 0) s = std::min(s, std::max(p.d - dot(p.n, from), 0.0) / rate);
  }
  return s;
}

BoundarySpectrum SolidBoundary::spectrum(const Xyz& u) const {
  // Facets that are nearly parallel (a tiny dihedral angle) leave a point that is on one's
  // plane to rounding possibly far from that facet's polygon: the closed form of the facet
  // that holds the point reproduces it; of the candidates, the best one is taken.
  std::size_t nearest = 0;
  const double d0 = distance(u, &nearest);
  BoundarySpectrum best = facet_spectrum(u, nearest);
  auto residual = [&](const BoundarySpectrum& s) {
    Xyz c;
    for (std::size_t k = 0; k < h_.size(); ++k) c = c + s.value(k) * h_[k];
    return (c - u).max_abs();
  };
  double best_residual = residual(best);
  for (std::size_t f = 0; f < planes_.size() && best_residual > 1e-13; ++f) {
    if (f == nearest || dot(planes_[f].n, u) - planes_[f].d < std::min(d0, 0.0) - 1e-10) continue;
    BoundarySpectrum s = facet_spectrum(u, f);
    const double r = residual(s);
    if (r < best_residual) best_residual = r, best = std::move(s);
  }
  return best;
}

BoundarySpectrum SolidBoundary::facet_spectrum(const Xyz& u, std::size_t facet) const {
  const Xyz n = planes_[facet].n;
  const std::size_t count = h_.size();
  std::vector<double> rho(count, 0.0);
  std::vector<std::size_t> in_plane;
  Xyz q = u;
  for (std::size_t k = 0; k < count; ++k) {
    const double v = dot(n, h_[k]);
    const double len = std::sqrt(dot(h_[k], h_[k]));
    if (std::abs(v) <= kInPlane * len) {
      in_plane.push_back(k);
    } else if (v > 0) {
      rho[k] = 1;
      q = q - h_[k];
    }
  }
  // q = sum over the facet's plane of rho_k h_k, rho_k in [0, 1]: a point of the facet's
  // zonogon, found in its own 2-D coordinates.
  const std::size_t m = in_plane.size();
  if (m == 1) {
    const Xyz& h = h_[in_plane[0]];
    rho[in_plane[0]] = std::clamp(dot(q, h) / dot(h, h), 0.0, 1.0);
  } else if (m >= 2) {
    Xyz e1 = h_[in_plane[0]];
    e1 = (1.0 / std::sqrt(dot(e1, e1))) * e1;
    const Xyz e2 = cross(n, e1);
    std::vector<std::array<double, 2>> g(m);
    for (std::size_t t = 0; t < m; ++t) g[t] = {dot(h_[in_plane[t]], e1), dot(h_[in_plane[t]], e2)};
    const double qx = dot(q, e1), qy = dot(q, e2);
    std::vector<double> r(m, 0.0);
    if (m == 2) {
      // q = a g0 + b g1 (Cramer).
      const double d = cross2(g[0][0], g[0][1], g[1][0], g[1][1]);
      if (d != 0) {
        r[0] = std::clamp(cross2(qx, qy, g[1][0], g[1][1]) / d, 0.0, 1.0);
        r[1] = std::clamp(cross2(g[0][0], g[0][1], qx, qy) / d, 0.0, 1.0);
      }
    } else {
      // The zonogon's boundary counter-clockwise from 0: edges g sorted by angle, then -g. A
      // fan of triangles (0, P_t, P_t+1) covers it; q's triangle gives rho as a blend of the
      // two vertices' 0/1 vectors, reduced below.
      std::vector<std::size_t> order(m);
      std::iota(order.begin(), order.end(), 0);
      // Angles relative to the cone's mean direction lie within (-pi/2, pi/2).
      double mx = 0, my = 0;
      for (const auto& v : g) {
        const double l = std::hypot(v[0], v[1]);
        mx += v[0] / l, my += v[1] / l;
      }
      auto angle = [&](std::size_t t) {
        return std::atan2(cross2(mx, my, g[t][0], g[t][1]), mx * g[t][0] + my * g[t][1]);
      };
      std::sort(order.begin(), order.end(),
                [&](std::size_t a, std::size_t b) { return angle(a) < angle(b); });
      std::vector<std::array<double, 2>> P(2 * m);
      P[0] = {0, 0};
      for (std::size_t s = 1; s <= m; ++s)
        P[s] = {P[s - 1][0] + g[order[s - 1]][0], P[s - 1][1] + g[order[s - 1]][1]};
      for (std::size_t s = 1; s < m; ++s)
        P[m + s] = {P[m + s - 1][0] - g[order[s - 1]][0], P[m + s - 1][1] - g[order[s - 1]][1]};
      auto mask_of = [&](std::size_t v, std::vector<double>& out, double w) {
        // vertex v <= m: the first v generators; vertex m + s: all but the first s.
        for (std::size_t t = 0; t < m; ++t) {
          const bool on = v <= m ? t < v : t >= v - m;
          if (on) out[order[t]] += w;
        }
      };
      double best = -INFINITY;
      std::size_t best_t = 1;
      double best_b = 0, best_c = 0;
      for (std::size_t t = 1; t + 1 < 2 * m; ++t) {
        const auto &p1 = P[t], &p2 = P[t + 1];
        const double d = cross2(p1[0], p1[1], p2[0], p2[1]);
        if (!(std::abs(d) > 0)) continue;
        const double b = cross2(qx, qy, p2[0], p2[1]) / d;
        const double c = cross2(p1[0], p1[1], qx, qy) / d;
        const double worst = std::min({b, c, 1 - b - c});
        if (worst > best) best = worst, best_t = t, best_b = b, best_c = c;
      }
      best_b = std::clamp(best_b, 0.0, 1.0);
      best_c = std::clamp(best_c, 0.0, 1.0 - best_b);
      mask_of(best_t, r, best_b);
      mask_of(best_t + 1, r, best_c);
      for (double& v : r) v = std::clamp(v, 0.0, 1.0);
      reduce_fractional(r, g);
    }
    for (std::size_t t = 0; t < m; ++t) rho[in_plane[t]] = r[t];
  }
  for (double& v : rho) v = snap01(v);
  return pack(rho);
}

LocusBoundary::LocusBoundary(std::span<const Xyz> columns, std::span<const double> basis)
    : samples_(columns.size()) {
  std::vector<std::size_t> pts;
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (basis[k] > 0 && columns[k].sum() > 0) pts.push_back(k);
  auto xy = [&](std::size_t k) {
    const double s = columns[k].sum();
    return Xyz{columns[k].X / s, columns[k].Y / s, 0};
  };
  // Andrew's monotone chain, counter-clockwise, collinear points dropped.
  std::sort(pts.begin(), pts.end(), [&](std::size_t a, std::size_t b) {
    const Xyz pa = xy(a), pb = xy(b);
    return pa.X < pb.X || (pa.X == pb.X && pa.Y < pb.Y);
  });
  auto turn = [&](std::size_t o, std::size_t a, std::size_t b) {
    const Xyz po = xy(o), pa = xy(a), pb = xy(b);
    return cross2(pa.X - po.X, pa.Y - po.Y, pb.X - po.X, pb.Y - po.Y);
  };
  std::vector<std::size_t> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = hull.size();
    for (std::size_t t = 0; t < pts.size(); ++t) {
      const std::size_t k = pass == 0 ? pts[t] : pts[pts.size() - 1 - t];
      while (hull.size() >= start + 2 && turn(hull[hull.size() - 2], hull.back(), k) <= 1e-15)
        hull.pop_back();
      hull.push_back(k);
    }
    hull.pop_back();
  }
  if (hull.size() < 3) throw Error("the grid's samples do not span a spectral locus");
  hull_ = hull;
  lower_ = {INFINITY, INFINITY, 0};
  upper_ = {-INFINITY, -INFINITY, 0};
  for (std::size_t k : hull_) {
    const Xyz c = xy(k);
    chroma_.push_back(c);
    sum_.push_back(columns[k].sum());
    lower_ = {std::min(lower_.X, c.X), std::min(lower_.Y, c.Y), 0};
    upper_ = {std::max(upper_.X, c.X), std::max(upper_.Y, c.Y), 0};
  }
  for (std::size_t e = 0; e < hull_.size(); ++e) {
    const Xyz a = chroma_[e], b = chroma_[(e + 1) % hull_.size()];
    Xyz n{b.Y - a.Y, a.X - b.X, 0};  // outward for a counter-clockwise polygon
    n = (1.0 / std::hypot(n.X, n.Y)) * n;
    planes_.push_back({n, dot(n, a)});
  }
}

double LocusBoundary::distance(const Xyz& p, std::size_t* edge) const {
  double best = -INFINITY;
  std::size_t at = 0;
  for (std::size_t e = 0; e < planes_.size(); ++e) {
    const double v = planes_[e].n.X * p.X + planes_[e].n.Y * p.Y - planes_[e].d;
    if (v > best) best = v, at = e;
  }
  if (edge) *edge = at;
  return best;
}

double LocusBoundary::max_step(const Xyz& from, const Xyz& to) const {
  double s = INFINITY;
  for (const Plane& p : planes_) {
    const double rate = p.n.X * (to.X - from.X) + p.n.Y * (to.Y - from.Y);
    if (rate > 0) s = std::min(s, std::max(p.d - p.n.X * from.X - p.n.Y * from.Y, 0.0) / rate);
  }
  return s;
}

BoundarySpectrum LocusBoundary::spectrum(const Xyz& p) const {
  // The edge whose segment is nearest to p (not only its line: short nearly collinear edges
  // at the red end).
  std::size_t edge = 0;
  double best = INFINITY;
  for (std::size_t e = 0; e < hull_.size(); ++e) {
    const Xyz a = chroma_[e], b = chroma_[(e + 1) % hull_.size()], d = b - a;
    const double t =
        std::clamp(((p.X - a.X) * d.X + (p.Y - a.Y) * d.Y) / (d.X * d.X + d.Y * d.Y), 0.0, 1.0);
    const double dist = std::hypot(a.X + t * d.X - p.X, a.Y + t * d.Y - p.Y);
    if (dist < best) best = dist, edge = e;
  }
  const std::size_t e1 = (edge + 1) % hull_.size();
  const Xyz a = chroma_[edge], b = chroma_[e1];
  const Xyz d = b - a;
  // p = (1 - t) a + t b; the light (1 - t) w_i / S_i + t w_j / S_j has X+Y+Z = 1 and that
  // chromaticity.
  const double t =
      std::clamp(((p.X - a.X) * d.X + (p.Y - a.Y) * d.Y) / (d.X * d.X + d.Y * d.Y), 0.0, 1.0);
  BoundarySpectrum s;
  s.mask.assign((samples_ + 31) / 32, 0u);
  s.i = static_cast<std::uint32_t>(hull_[edge]);
  s.j = static_cast<std::uint32_t>(hull_[e1]);
  s.a = (1 - t) / sum_[edge];
  s.b = t / sum_[e1];
  return s;
}

}  // namespace spectralize
