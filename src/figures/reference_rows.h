#pragma once
// The validation's reference lines (docs/MODEL_STUDY.md): rows of the reflectance tables that
// are not registered models, for comparison. "What data alone achieves": each patch predicted
// from its nearest neighbour among the other development patches.

#include <vector>

#include "figures/validation.h"

namespace spectralize::figures {

/// The reference rows, in table order. Cost: O(1).
std::vector<ValidationConfig> reference_rows();

/// Leave-one-out nearest neighbour: the measured reflectance of the development patch (any
/// set, the patch itself left out) nearest in CIEDE2000 under D65 to the patch's colour,
/// projected onto the exact spectra of that colour within 0 <= rho <= 1 (least squares,
/// docs/DESIGN.md §5). Exact, bounded, not continuous in the colour. Cost: O(patches) per patch.
ValidationConfig nearest_neighbour_row();

}  // namespace spectralize::figures
