#pragma once
// spectralize.colour_space(name): what is known of a colour space of the OCIO config, from
// the one place the tool and the module decide it (colour/colour_space.h).

#include <pybind11/pybind11.h>

namespace spectralize::python {

/// Adds colour_space() to the module. Cost: O(1).
void add_colour_space(pybind11::module_& m);

}  // namespace spectralize::python
