#pragma once
// The validation's reference lines (docs/MODEL_STUDY.md): rows of the reflectance tables that
// are not registered models, for comparison: rgb2spec as renderers use it (Jakob & Hanika 2019,
// src/baseline), fitted per colour and through pbrt-v4's 64^3 table; and "what data alone
// achieves", each patch predicted from its nearest neighbour among the other development
// patches.

#include <vector>

#include "figures/validation.h"

namespace spectralize::figures {

/// The reference rows, in table order. Cost: O(1).
std::vector<ValidationConfig> reference_rows();

/// rgb2spec fitted to each patch's RGB directly (Levenberg-Marquardt in CIELAB, the best the
/// sigmoid family does; not exact: the fit stops at its own Delta E). Cost: ~3 us per patch.
ValidationConfig rgb2spec_fit_row();

/// rgb2spec through pbrt-v4's table of 3 x 64^3 nodes (what a renderer evaluates: trilinear
/// blend of float coefficients). Cost: the table, ~2 s per space on 2 threads, then O(1).
ValidationConfig rgb2spec_table_row();

/// Leave-one-out nearest neighbour: the measured reflectance of the development patch (any
/// set, the patch itself left out) nearest in CIEDE2000 under D65 to the patch's colour,
/// projected onto the exact spectra of that colour within 0 <= rho <= 1 (least squares,
/// docs/DESIGN.md §5). Exact, bounded, not continuous in the colour. Cost: O(patches) per patch.
ValidationConfig nearest_neighbour_row();

}  // namespace spectralize::figures
