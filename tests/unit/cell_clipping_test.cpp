// Clipping a cell to a convex gamut (docs/DESIGN.md §14): the simplices cover exactly the part
// of the box inside the half-spaces (volumes against geometry worked out here, points sampled
// inside and outside), every vertex lies in them, and barycentric maps give back the vertices.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/gamut/cell_clipping.h"

namespace spectralize {
namespace {

double tet_volume(const ClippedCell& c, const std::array<int, 4>& s) {
  const Xyz a = c.vertices[s[1]].p - c.vertices[s[0]].p,
            b = c.vertices[s[2]].p - c.vertices[s[0]].p,
            d = c.vertices[s[3]].p - c.vertices[s[0]].p;
  return std::abs(dot(a, cross(b, d))) / 6;
}

double volume(const ClippedCell& c) {
  double v = 0;
  for (const auto& s : c.simplices) v += tet_volume(c, s);
  return v;
}

// The simplices holding p (all barycentric weights >= -tol).
int holders(const ClippedCell& c, const Xyz& p, bool planar, double tol = 1e-12) {
  int n = 0;
  for (const auto& s : c.simplices) {
    const auto m = barycentric_map(c.vertices[s[0]].p, c.vertices[s[1]].p, c.vertices[s[2]].p,
                                   c.vertices[s[3]].p, planar);
    const Xyz d = p - Xyz{m[9], m[10], m[11]};
    const double w1 = m[0] * d.X + m[1] * d.Y + m[2] * d.Z,
                 w2 = m[3] * d.X + m[4] * d.Y + m[5] * d.Z;
    const double w3 = planar ? 0 : m[6] * d.X + m[7] * d.Y + m[8] * d.Z;
    if (std::min({1 - w1 - w2 - w3, w1, w2, w3}) >= -tol) ++n;
  }
  return n;
}

Plane plane(Xyz n, double d) {
  const double len = std::sqrt(dot(n, n));
  return {(1 / len) * n, d / len};
}

TEST(ClipBox, AHalfSpaceThroughTheCubeLeavesItsVolume) {
  // x + y + z <= 1.5 holds half the unit cube (symmetry about its centre).
  const std::vector<Plane> planes = {plane({1, 1, 1}, 1.5)};
  const ClippedCell c = clip_box({0, 0, 0}, {1, 1, 1}, planes, 1e-12);
  EXPECT_NEAR(volume(c), 0.5, 1e-12);
  for (const ClipVertex& v : c.vertices) {
    EXPECT_LE(v.p.X + v.p.Y + v.p.Z, 1.5 + 1e-12);
  }
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 2000; ++k) {
    const Xyz p{u(rng), u(rng), u(rng)};
    const double side = p.X + p.Y + p.Z - 1.5;
    if (side < -1e-9) {
      EXPECT_GE(holders(c, p, false), 1) << p.X << "," << p.Y << "," << p.Z;
    }
    if (side > 1e-9) {
      EXPECT_EQ(holders(c, p, false), 0);
    }
  }
}

TEST(ClipBox, PlanesThatMissKeepTheBoxAndPlanesThatCoverItEmptyIt) {
  const ClippedCell whole =
      clip_box({0, 0, 0}, {2, 1, 1}, std::vector<Plane>{plane({1, 0, 0}, 5)}, 1e-12);
  EXPECT_NEAR(volume(whole), 2.0, 1e-12);
  EXPECT_EQ(whole.vertices.size(), 8u);
  const ClippedCell none =
      clip_box({0, 0, 0}, {1, 1, 1}, std::vector<Plane>{plane({1, 0, 0}, -0.5)}, 1e-12);
  EXPECT_TRUE(none.simplices.empty());
  // Touching a face only: no volume.
  const ClippedCell face =
      clip_box({0, 0, 0}, {1, 1, 1}, std::vector<Plane>{plane({1, 0, 0}, 0)}, 1e-12);
  EXPECT_TRUE(face.simplices.empty());
}

TEST(ClipBox, ACornerCutByManyPlanesIsCoveredWhollyAndCornersAreKept) {
  // Planes tangent to the sphere of radius 0.8 around the origin (normals in the positive
  // octant) cut away the far part of [0, 1]^3.
  std::vector<Plane> planes;
  for (int i = 1; i <= 6; ++i)
    for (int j = 1; j <= 6; ++j) {
      const double t = M_PI / 2 * i / 7, p = M_PI / 2 * j / 7;
      planes.push_back(
          plane({std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)}, 0.8));
    }
  const ClippedCell c = clip_box({0, 0, 0}, {1, 1, 1}, planes, 1e-12);
  int corners = 0;
  for (const ClipVertex& v : c.vertices) {
    corners += v.corner >= 0;
    for (const Plane& pl : planes) {
      EXPECT_LE(dot(pl.n, v.p), pl.d + 1e-12);
    }
  }
  int kept = 0;  // the box's corners inside every plane are vertices of the clipped cell
  for (int k = 0; k < 8; ++k) {
    const Xyz q{double(k & 1), double((k >> 1) & 1), double(k >> 2)};
    bool in = true;
    for (const Plane& pl : planes) in = in && dot(pl.n, q) <= pl.d;
    kept += in;
  }
  EXPECT_EQ(corners, kept);
  EXPECT_GE(kept, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  int inside = 0;
  for (int k = 0; k < 5000; ++k) {
    const Xyz p{u(rng), u(rng), u(rng)};
    double worst = -INFINITY;
    for (const Plane& pl : planes) worst = std::max(worst, dot(pl.n, p) - pl.d);
    if (worst < -1e-9) {
      EXPECT_GE(holders(c, p, false), 1);
      ++inside;
    }
    if (worst > 1e-9) {
      EXPECT_EQ(holders(c, p, false), 0);
    }
  }
  EXPECT_GT(inside, 1000);
}

TEST(ClipRectangle, ATriangleClipsASquareToItsArea) {
  // The half-planes of the triangle (0,0), (2,0), (0,2): x >= 0, y >= 0, x + y <= 2; the unit
  // square [0.5, 1.5]^2 keeps half (the corner triangle beyond x + y = 2 has legs 1).
  const std::vector<Plane> planes = {plane({-1, 0, 0}, 0), plane({0, -1, 0}, 0),
                                     plane({1, 1, 0}, 2)};
  const ClippedCell c = clip_rectangle({0.5, 0.5, 0}, {1.5, 1.5, 0}, planes, 1e-12);
  double area = 0;
  for (const auto& s : c.simplices) {
    const Xyz a = c.vertices[s[1]].p - c.vertices[s[0]].p,
              b = c.vertices[s[2]].p - c.vertices[s[0]].p;
    area += std::abs(a.X * b.Y - a.Y * b.X) / 2;
    EXPECT_EQ(s[3], s[0]);
  }
  EXPECT_NEAR(area, 0.5, 1e-12);
  EXPECT_GE(holders(c, {0.7, 0.7, 0}, true), 1);
  EXPECT_EQ(holders(c, {1.4, 1.4, 0}, true), 0);
}

TEST(BarycentricMap, GivesBackTheVertices) {
  const Xyz v[4] = {{0.1, 0.2, 0.3}, {1.0, 0.1, 0.2}, {0.2, 0.9, 0.1}, {0.3, 0.3, 1.2}};
  const auto m = barycentric_map(v[0], v[1], v[2], v[3], false);
  for (int k = 0; k < 4; ++k) {
    const Xyz d = v[k] - Xyz{m[9], m[10], m[11]};
    const double w[3] = {m[0] * d.X + m[1] * d.Y + m[2] * d.Z, m[3] * d.X + m[4] * d.Y + m[5] * d.Z,
                         m[6] * d.X + m[7] * d.Y + m[8] * d.Z};
    for (int j = 1; j < 4; ++j) {
      EXPECT_NEAR(w[j - 1], k == j ? 1.0 : 0.0, 1e-12);
    }
  }
}

}  // namespace
}  // namespace spectralize
