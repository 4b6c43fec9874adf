#pragma once
// CIELAB (CIE 015) and the CIEDE2000 colour difference (CIE 142; Sharma, Wu & Dalal 2005), for
// measuring how far two renders or two spectra are apart as a person would see it, and
// CIEDE2000's local metric, the exemplar model's distance to its measured colours
// (docs/DESIGN.md §6).

#include "spectralize/core/xyz.h"

namespace spectralize {

/// A CIELAB colour: L* (0 black .. 100 white), a*, b*.
struct Lab {
  double L = 0, a = 0, b = 0;
};

/// CIELAB of `xyz` relative to the reference white `white` (same units: only ratios matter).
/// Uses the CIE's linear segment below (6/29)^3, so black and negative values stay finite.
/// Cost: O(1), three cube roots.
Lab to_lab(const Xyz& xyz, const Xyz& white);

/// The CIEDE2000 difference of two CIELAB colours (kL = kC = kH = 1), symmetric, exactly 0
/// for equal colours. Cost: O(1), a few transcendental functions.
double delta_e_2000(const Lab& lab1, const Lab& lab2);

/// CIEDE2000's metric at one colour: the quadratic form with
/// delta_e_2000(at, at + d)^2 = d^T Q d + O(|d|^3) for small CIELAB steps d (S_L, S_C, S_H, R_T
/// and the a* stretch G taken at that colour). Smooth in d, where CIEDE2000 itself jumps where
/// the mean hue of a pair wraps, so distances measured with it are continuous.
struct LabMetric {
  double ll = 1, aa = 1, ab = 0, bb = 1;  // Q = [[ll, 0, 0], [0, aa, ab], [0, ab, bb]]
  /// d^T Q d. Cost: O(1).
  double squared(double dl, double da, double db) const {
    return ll * dl * dl + aa * da * da + 2 * ab * da * db + bb * db * db;
  }
};

/// The metric of CIEDE2000 (kL = kC = kH = 1) at `at`. Cost: O(1), a few transcendental
/// functions.
LabMetric ciede2000_metric(const Lab& at);

}  // namespace spectralize
