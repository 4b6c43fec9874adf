#pragma once
// The part of a table cell inside a convex gamut (docs/DESIGN.md §14): a box (or a rectangle)
// clipped by the gamut's facet planes, cut into simplices whose vertices are the box's corners
// inside the gamut and points on its boundary. Blending the exact spectra of a simplex's
// vertices with barycentric weights is exact for every point of the simplex (colour is linear
// in the spectrum) and stays within the bounds (a convex combination).

#include <array>
#include <span>
#include <vector>

#include "core/gamut/gamut_boundary.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

/// A vertex of a clipped cell: a corner of the box (corner >= 0: bit 0 x, bit 1 y, bit 2 z
/// upper), or a point on the plane `plane` (an index into the planes given).
struct ClipVertex {
  Xyz p;
  int corner = -1;
  int plane = -1;
};

/// A clipped cell cut into simplices (tetrahedra; triangles in 2-D, whose fourth vertex
/// repeats the first), each given by four indices into `vertices`.
struct ClippedCell {
  std::vector<ClipVertex> vertices;
  std::vector<std::array<int, 4>> simplices;
};

/// The box [lower, upper] intersected with the half-spaces n . p <= d of `planes` (only those
/// that cut the box matter), cut into tetrahedra: a fan over the faces from the vertex nearest
/// to `apex` (the black point: near it the fan's simplices are cones from black, so a colour
/// of any darkness is as well covered as a bright one); slivers of relative volume below 1e-12
/// are dropped. `eps`: distances within it are on a plane. Empty when the intersection has no
/// volume. Cost: O(cutting planes x vertices).
ClippedCell clip_box(const Xyz& lower, const Xyz& upper, std::span<const Plane> planes, double eps,
                     const Xyz& apex = {});

/// The rectangle [lower, upper] (x, y) intersected with the half-planes of `planes`, cut into
/// triangles (a fan). Cost: O(planes x vertices).
ClippedCell clip_rectangle(const Xyz& lower, const Xyz& upper, std::span<const Plane> planes,
                           double eps);

/// The affine map of a simplex: weights w1..w3 = M (p - v0) (w0 = 1 - w1 - w2 - w3), as
/// M row-major then v0; 2-D: M is 2x2 in entries 0, 1, 3, 4 (others 0). Cost: O(1).
std::array<double, 12> barycentric_map(const Xyz& v0, const Xyz& v1, const Xyz& v2, const Xyz& v3,
                                       bool planar);

}  // namespace spectralize
