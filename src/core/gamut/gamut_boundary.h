#pragma once
// The boundaries of the two gamuts as the exact table needs them (docs/DESIGN.md §14): facet
// planes in the table's own coordinates, the signed distance of a point to the gamut, and the
// exact spectrum of a point on the boundary, which is (almost) unique and needs no solver:
// - the reflectance solid {W rho : 0 <= rho <= 1} is a zonotope; on its facet with normal n,
//   rho_k = 1 where n . w_k > 0, 0 where < 0, and only the generators in the facet's plane are
//   fractional, reduced to at most two;
// - the spectral locus (the chromaticities of the sample weights; their convex hull for a
//   sampled grid) has straight edges between two samples' chromaticities, and a point on an
//   edge is the light of those two samples only.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/colorimetry/mat3.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

/// A half-space n . p <= d with a unit normal n (2-D planes have n.Z = 0).
struct Plane {
  Xyz n;
  double d = 0;
};

/// The exact spectrum of a point on a gamut's boundary: every sample 0 or 1 (`mask`) except
/// samples i and j, which have the values a and b (i == j when only one is set apart).
struct BoundarySpectrum {
  std::vector<std::uint32_t> mask;  // bit k % 32 of word k / 32: sample k is 1
  std::uint32_t i = 0, j = 0;
  double a = 0, b = 0;

  /// Sample k. Cost: O(1).
  double value(std::size_t k) const {
    if (k == i) return a;
    if (k == j) return b;
    return (mask[k / 32] >> (k % 32)) & 1u ? 1.0 : 0.0;
  }
};

/// The reflectance solid in a linear frame u = frame^-1 . target (the exact table's RGB).
class SolidBoundary {
 public:
  /// The facets of {W rho} for the weight columns W (targets) seen in the frame whose columns
  /// are the targets of the frame's unit vectors. Duplicate planes (coplanar generators) are
  /// merged. Cost: O(N^3) (N^2 / 2 pairs, each summed over N generators).
  SolidBoundary(std::span<const Xyz> columns, const Mat3& target_from_frame);

  /// The facet planes in the frame. Cost: O(1).
  const std::vector<Plane>& planes() const { return planes_; }
  /// max over facets of n . u - d: <= 0 inside; the facet attaining it in `facet`.
  /// Cost: O(facets).
  double distance(const Xyz& u, std::size_t* facet = nullptr) const;
  /// The exact spectrum of a point on the boundary (within rounding); values in [0, 1]. Of
  /// the facets whose planes pass within 1e-10 of u (nearly parallel ones among them: the
  /// generators near 650 nm have tiny zbar), the one whose closed form reproduces u best.
  /// Cost: O(N) per such facet (O(N^2) when many generators lie in a facet's plane).
  BoundarySpectrum spectrum(const Xyz& u) const;
  /// The solid's bounding box in the frame. Cost: O(1).
  Xyz lower() const { return lower_; }
  Xyz upper() const { return upper_; }
  /// The largest s with from + s (to - from) inside (from inside). Cost: O(facets).
  double max_step(const Xyz& from, const Xyz& to) const;
  /// The facets whose planes cut the box [lower, upper] (some corner beyond d + eps times the
  /// box's largest coordinate).
  /// Cost: O(facets).
  std::vector<Plane> cutting(const Xyz& lower, const Xyz& upper, double eps) const;

 private:
  BoundarySpectrum facet_spectrum(const Xyz& u, std::size_t facet) const;
  std::vector<Xyz> h_;  // the generators in the frame
  std::vector<Plane> planes_;
  std::vector<double> nx_, ny_, nz_, d_;  // the planes again, one array per component (SIMD)
  Xyz lower_, upper_;
};

/// The spectral locus of a grid as a convex polygon in CIE xy chromaticity.
class LocusBoundary {
 public:
  /// The hull of the chromaticities of the weight columns W of the samples with basis > 0.
  /// Throws Error when fewer than three samples span it. Cost: O(N log N).
  LocusBoundary(std::span<const Xyz> columns, std::span<const double> basis);

  /// The polygon's edges as lines (n.Z = 0) in (x, y). Cost: O(1).
  const std::vector<Plane>& planes() const { return planes_; }
  /// max over edges of n . p - d for p = (x, y, 0). Cost: O(edges).
  double distance(const Xyz& p, std::size_t* edge = nullptr) const;
  /// The exact spectrum of X+Y+Z = 1 at a point of the boundary: two samples (of the edges
  /// passing within 1e-10 of p, the one nearest to it). Cost: O(N + edges).
  BoundarySpectrum spectrum(const Xyz& p) const;
  /// The polygon's bounding box in (x, y). Cost: O(1).
  Xyz lower() const { return lower_; }
  Xyz upper() const { return upper_; }
  /// The largest s with from + s (to - from) inside (from inside), in (x, y). Cost: O(edges).
  double max_step(const Xyz& from, const Xyz& to) const;

 private:
  std::vector<std::size_t> hull_;  // sample indices, counter-clockwise
  std::vector<Xyz> chroma_;        // (x, y, 0) per hull vertex
  std::vector<double> sum_;        // X + Y + Z of each hull vertex's weight column
  std::vector<Plane> planes_;      // edge hull_[e] -> hull_[e + 1]
  std::size_t samples_ = 0;
  Xyz lower_, upper_;
};

}  // namespace spectralize
