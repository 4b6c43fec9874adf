#include "core/gamut/cell_clipping.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/colorimetry/mat3.h"

namespace spectralize {

namespace {

Xyz corner_of(const Xyz& lower, const Xyz& upper, int c) {
  return {c & 1 ? upper.X : lower.X, c & 2 ? upper.Y : lower.Y, c & 4 ? upper.Z : lower.Z};
}

// Newell's normal of a polygon (not normalised): its direction follows the vertex order.
Xyz newell(const std::vector<ClipVertex>& v, const std::vector<int>& face) {
  Xyz n;
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Xyz& a = v[face[k]].p;
    const Xyz& b = v[face[(k + 1) % face.size()]].p;
    n.X += (a.Y - b.Y) * (a.Z + b.Z);
    n.Y += (a.Z - b.Z) * (a.X + b.X);
    n.Z += (a.X - b.X) * (a.Y + b.Y);
  }
  return n;
}

struct Polytope {
  std::vector<ClipVertex> v;
  std::vector<std::vector<int>> faces;  // counter-clockwise seen from outside
};

Polytope box(const Xyz& lower, const Xyz& upper) {
  Polytope P;
  for (int c = 0; c < 8; ++c) P.v.push_back({corner_of(lower, upper, c), c, -1});
  for (int axis = 0; axis < 3; ++axis) {
    const int b = 1 << ((axis + 1) % 3), c = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const int s = side ? 1 << axis : 0;
      std::vector<int> f = {s, s | b, s | b | c, s | c};
      // Outward is -axis on the lower side, +axis on the upper.
      const double out = dot(
          newell(P.v, f), Xyz{axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0});
      if ((out > 0) != (side == 1)) std::reverse(f.begin(), f.end());
      P.faces.push_back(f);
    }
  }
  return P;
}

// Clips P to n . p <= d. Returns false when nothing of positive volume is left.
bool clip(Polytope& P, const Plane& plane, int plane_index, double eps) {
  const std::size_t nv = P.v.size();
  std::vector<double> dist(nv);
  std::vector<int> side(nv);
  bool out = false, in = false;
  for (std::size_t i = 0; i < nv; ++i) {
    dist[i] = dot(plane.n, P.v[i].p) - plane.d;
    // Relative to the point's distance from black (the origin): near black the gamut is a
    // cone, and a dark colour's vertices are as precise as a bright one's.
    const double tol = eps * P.v[i].p.max_abs();
    side[i] = dist[i] > tol ? 1 : dist[i] < -tol ? -1 : 0;
    out = out || side[i] > 0;
    in = in || side[i] < 0;
  }
  if (!out) return true;
  if (!in) return false;
  std::map<std::pair<int, int>, int> cut;
  auto crossing = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = cut.find(key);
    if (it != cut.end()) return it->second;
    const double t = dist[a] / (dist[a] - dist[b]);
    const Xyz p = P.v[a].p + t * (P.v[b].p - P.v[a].p);
    P.v.push_back({p, -1, plane_index});
    side.push_back(0);
    const int index = static_cast<int>(P.v.size()) - 1;
    cut.emplace(key, index);
    return index;
  };
  std::vector<std::vector<int>> faces;
  for (const auto& f : P.faces) {
    std::vector<int> kept;
    for (std::size_t k = 0; k < f.size(); ++k) {
      const int a = f[k], b = f[(k + 1) % f.size()];
      if (side[a] <= 0) kept.push_back(a);
      if ((side[a] < 0 && side[b] > 0) || (side[a] > 0 && side[b] < 0))
        kept.push_back(crossing(a, b));
    }
    if (kept.size() >= 3) faces.push_back(std::move(kept));
  }
  // The new face: every vertex now on the plane, in angular order around their centroid.
  std::vector<int> cap;
  for (std::size_t i = 0; i < P.v.size(); ++i)
    if (side[i] == 0) cap.push_back(static_cast<int>(i));
  if (cap.size() >= 3) {
    Xyz c;
    for (int i : cap) c = c + P.v[i].p;
    c = (1.0 / static_cast<double>(cap.size())) * c;
    const Xyz n = plane.n;
    Xyz e1 = std::abs(n.X) < 0.9 ? cross(n, Xyz{1, 0, 0}) : cross(n, Xyz{0, 1, 0});
    e1 = (1.0 / std::sqrt(dot(e1, e1))) * e1;
    const Xyz e2 = cross(n, e1);  // (e1, e2, n) right-handed: angles grow counter-clockwise
    std::vector<std::pair<double, int>> order;
    for (int i : cap) {
      const Xyz d = P.v[i].p - c;
      order.push_back({std::atan2(dot(d, e2), dot(d, e1)), i});
    }
    std::sort(order.begin(), order.end());
    std::vector<int> f;
    for (const auto& [angle, i] : order) f.push_back(i);
    faces.push_back(std::move(f));
  }
  // Keep the vertices still in use, renumbered.
  std::vector<int> remap(P.v.size(), -1);
  std::vector<ClipVertex> v;
  for (auto& f : faces)
    for (int& i : f) {
      if (remap[i] < 0) remap[i] = static_cast<int>(v.size()), v.push_back(P.v[i]);
      i = remap[i];
    }
  P.v = std::move(v);
  P.faces = std::move(faces);
  return P.faces.size() >= 4;
}

double triple(const Xyz& a, const Xyz& b, const Xyz& c) {
  return dot(a, cross(b, c));
}

}  // namespace

ClippedCell clip_box(const Xyz& lower, const Xyz& upper, std::span<const Plane> planes, double eps,
                     const Xyz& apex_hint) {
  Polytope P = box(lower, upper);
  const Xyz centre = 0.5 * (lower + upper), half = 0.5 * (upper - lower);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Plane& pl = planes[i];
    // Only planes that cut the box (its support beyond d) change anything.
    const double support = dot(pl.n, centre) + std::abs(pl.n.X) * half.X +
                           std::abs(pl.n.Y) * half.Y + std::abs(pl.n.Z) * half.Z;
    if (support <= pl.d + eps * std::max(lower.max_abs(), upper.max_abs())) continue;
    if (!clip(P, pl, static_cast<int>(i), eps)) return {};
  }
  ClippedCell cell;
  cell.vertices = P.v;
  int apex = 0;
  for (std::size_t i = 1; i < P.v.size(); ++i) {
    const Xyz d = P.v[i].p - apex_hint, e = P.v[apex].p - apex_hint;
    if (dot(d, d) < dot(e, e)) apex = static_cast<int>(i);
  }
  // A fan from the apex over every face that does not contain it; slivers below the relative
  // volume 1e-12 are dropped (their points lie within rounding of a neighbour, relative to
  // their distance from the apex).
  const double volume = half.X * half.Y * half.Z * 8;
  for (const auto& f : P.faces) {
    if (std::find(f.begin(), f.end(), apex) != f.end()) continue;
    for (std::size_t k = 1; k + 1 < f.size(); ++k) {
      const Xyz& a = P.v[apex].p;
      const double v6 = triple(P.v[f[0]].p - a, P.v[f[k]].p - a, P.v[f[k + 1]].p - a);
      if (std::abs(v6) <= 1e-12 * volume) continue;
      cell.simplices.push_back({apex, f[0], f[k], f[k + 1]});
    }
  }
  if (cell.simplices.empty()) return {};
  return cell;
}

ClippedCell clip_rectangle(const Xyz& lower, const Xyz& upper, std::span<const Plane> planes,
                           double eps) {
  std::vector<ClipVertex> poly = {{{lower.X, lower.Y, 0}, 0, -1},
                                  {{upper.X, lower.Y, 0}, 1, -1},
                                  {{upper.X, upper.Y, 0}, 3, -1},
                                  {{lower.X, upper.Y, 0}, 2, -1}};
  for (std::size_t i = 0; i < planes.size() && !poly.empty(); ++i) {
    const Plane& pl = planes[i];
    std::vector<double> dist(poly.size());
    bool out = false;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      dist[k] = pl.n.X * poly[k].p.X + pl.n.Y * poly[k].p.Y - pl.d;
      if (std::abs(dist[k]) <= eps) dist[k] = 0;
      out = out || dist[k] > 0;
    }
    if (!out) continue;
    std::vector<ClipVertex> next;
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const std::size_t l = (k + 1) % poly.size();
      if (dist[k] <= 0) next.push_back(poly[k]);
      if ((dist[k] < 0 && dist[l] > 0) || (dist[k] > 0 && dist[l] < 0)) {
        const double t = dist[k] / (dist[k] - dist[l]);
        next.push_back({poly[k].p + t * (poly[l].p - poly[k].p), -1, static_cast<int>(i)});
      }
    }
    poly = std::move(next);
  }
  ClippedCell cell;
  if (poly.size() < 3) return cell;
  cell.vertices = poly;
  const double area = (upper.X - lower.X) * (upper.Y - lower.Y);
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    const Xyz a = poly[k].p - poly[0].p, b = poly[k + 1].p - poly[0].p;
    if (std::abs(a.X * b.Y - a.Y * b.X) <= 1e-12 * area) continue;
    cell.simplices.push_back({0, static_cast<int>(k), static_cast<int>(k + 1), 0});
  }
  if (cell.simplices.empty()) cell.vertices.clear();
  return cell;
}

std::array<double, 12> barycentric_map(const Xyz& v0, const Xyz& v1, const Xyz& v2, const Xyz& v3,
                                       bool planar) {
  std::array<double, 12> m{};
  if (planar) {
    const double a = v1.X - v0.X, b = v2.X - v0.X, c = v1.Y - v0.Y, d = v2.Y - v0.Y;
    const double det2 = a * d - b * c;
    m[0] = d / det2, m[1] = -b / det2, m[3] = -c / det2, m[4] = a / det2;
  } else {
    const Mat3 inv = inverse(from_columns(v1 - v0, v2 - v0, v3 - v0));
    std::copy(inv.begin(), inv.end(), m.begin());
  }
  m[9] = v0.X, m[10] = v0.Y, m[11] = v0.Z;
  return m;
}

}  // namespace spectralize
