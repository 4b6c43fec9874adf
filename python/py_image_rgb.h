#pragma once
// spectralize.read_rgb(): an image's linear RGB as the CLI decides its colour space (for
// renderer plugins that uplift at render time, spectralize.mitsuba).

#include <pybind11/pybind11.h>

namespace spectralize::python {

/// Adds read_rgb to the module. Cost: O(1).
void add_image_rgb(pybind11::module_& m);

}  // namespace spectralize::python
