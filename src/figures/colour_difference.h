#pragma once
// CIELAB (CIE 015) and the CIEDE2000 colour difference (CIE 142; Sharma, Wu & Dalal 2005), for
// measuring how far two renders or two spectra are apart as a person would see it.

#include "core/xyz.h"

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

}  // namespace spectralize
