#pragma once
// spectralize.rt: render-time tables (.spztab) from Python, over the same evaluator as the C
// library (include/spectralize/rt.hpp): load a table, fetch the spectra of a NumPy array of
// colours at table speed, without the solver.

#include <pybind11/pybind11.h>

namespace spectralize::python {

/// Adds the submodule `rt` (class Table) to `m`. Cost: O(1).
void add_rt_module(pybind11::module_& m);

}  // namespace spectralize::python
