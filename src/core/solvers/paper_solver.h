#pragma once
// The paper's spectralizer (Zhdanov & Potemin, eqs. 2-5): the average of all admissible
// partial solutions, i.e. of all non-negative solutions that are non-zero at three
// wavelengths only, after the edge-peak filter.
//
// Instead of solving C(N,3) 3x3 systems, it works in the chromaticity plane: a triple is
// admissible exactly when the target's chromaticity lies in the triangle of the three samples'
// chromaticities, and its densities are the barycentric coordinates scaled by S/s_m. Sorting
// the samples by angle around the target turns "contains the target" into contiguous index
// ranges, so only admissible triples are visited (docs/DESIGN.md §2, "the fast form").

#include <cstddef>
#include <span>
#include <vector>

#include "spectralize/core/edge_filter.h"
#include "spectralize/core/xyz.h"

namespace spectralize {

struct PaperSpectrum {
  std::vector<double> values;  // per grid sample; the average over the kept partial solutions
  std::size_t admissible = 0;  // L: admissible partial solutions
  std::size_t dropped = 0;     // K actually dropped by the edge filter (ties at the cut kept)
};

class PaperSolver {
 public:
  /// Prepares the solver for the sample weight vectors of a grid; `wavelengths` (nm, one per
  /// sample) locate the edge bands and the 400-700 nm interior for EdgeFilter::automatic().
  /// Cost: O(N).
  PaperSolver(std::span<const Xyz> weights, std::span<const double> wavelengths);
  /// As above without wavelengths: EdgeFilter::automatic() then stops at its first step.
  /// Cost: O(N).
  explicit PaperSolver(std::span<const Xyz> weights) : PaperSolver(weights, {}) {}

  /// The edge bands the automatic filter keeps free of peaks. Cost: O(1).
  const EdgeBands& edge_bands() const { return bands_; }

  /// The filtered average for `target` (any positive multiple of a colour inside the grid's
  /// spectral locus; returns admissible == 0 otherwise). Thread-safe.
  /// Cost: O(N^2 + L), with L ~ 0.2 * C(N,3); ~2 passes over L when filtering.
  PaperSpectrum solve(const Xyz& target, const EdgeFilter& filter) const;

  /// Unnormalised sum of all admissible partial solutions, written to `sum` (size N); returns L.
  /// The benchmarked kernel. Thread-safe. Cost: O(N^2 + L).
  std::size_t sum_admissible(const Xyz& target, std::span<double> sum) const;

 private:
  std::vector<std::size_t> active_;  // samples with a non-zero weight vector
  EdgeBands bands_;
  std::vector<double> chroma_x_, chroma_y_, weight_sum_;
  std::size_t n_;
};

}  // namespace spectralize
