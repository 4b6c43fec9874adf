#include "py_submodules.h"

#include <string>
#include <string_view>

namespace spectralize::embedded {
extern const std::string_view kMitsubaPlugins;  // python/mitsuba_plugins.py
extern const std::string_view kUsdStages;       // python/usd_stages.py
}  // namespace spectralize::embedded

namespace py = pybind11;

namespace spectralize::python {

namespace {

// Runs `source` as the submodule `name` of `m`, registered in sys.modules so that
// `import spectralize.name` finds it; tracebacks name `file`.
void add_submodule(py::module_& m, const char* name, std::string_view source, const char* file) {
  py::module_ sub = m.def_submodule(name);
  const std::string full = m.attr("__name__").cast<std::string>() + "." + name;
  sub.attr("__file__") = file;
  py::module_::import("sys").attr("modules")[py::str(full)] = sub;
  const py::module_ builtins = py::module_::import("builtins");
  const py::object code =
      builtins.attr("compile")(py::str(source.data(), source.size()), file, "exec");
  builtins.attr("exec")(code, sub.attr("__dict__"));
}

}  // namespace

void add_python_submodules(py::module_& m) {
  add_submodule(m, "mitsuba", embedded::kMitsubaPlugins, "spectralize/mitsuba.py");
  add_submodule(m, "usd", embedded::kUsdStages, "spectralize/usd.py");
}

}  // namespace spectralize::python
