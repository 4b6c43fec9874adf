#pragma once
// How far two renders are apart as a person would see it: CIEDE2000 per pixel in CIELAB
// relative to the scene's white, and its mean, 95th percentile and maximum over a set of pixels.

#include <vector>

#include "spectralize/core/xyz.h"

namespace spectralize::path_tracer {

/// Summary of per-pixel colour differences.
struct DeltaEStats {
  double mean = 0, p95 = 0, max = 0;
  std::size_t pixels = 0;
};

/// CIEDE2000 between a[i] and b[i] for every pixel, CIELAB relative to `white`. Throws Error for
/// images of different sizes. Cost: O(pixels).
std::vector<double> delta_e_map(const std::vector<Xyz>& a, const std::vector<Xyz>& b,
                                const Xyz& white);

/// Mean, p95 (the nearest-rank 95th percentile) and max of delta_e over the pixels whose
/// `mask` is true (all when `mask` is empty). Cost: O(pixels log pixels).
DeltaEStats summarize(const std::vector<double>& delta_e, const std::vector<bool>& mask = {});

}  // namespace spectralize::path_tracer
