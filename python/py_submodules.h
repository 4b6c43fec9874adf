#pragma once
// The module's pure-Python submodules (python/*.py compiled in as text): importable as
// `import spectralize.<name>` like any submodule of a package.

#include <pybind11/pybind11.h>

namespace spectralize::python {

/// Adds spectralize.mitsuba (python/mitsuba_plugins.py). Cost: compiling its source, ~1 ms.
void add_python_submodules(pybind11::module_& m);

}  // namespace spectralize::python
