#include "py_options.h"

#include <algorithm>

#include "spectralize/core/error.h"

namespace py = pybind11;

namespace spectralize::python {

bool OptionScope::takes(const SettingSpec& spec) const {
  const std::string key(spec.key);
  if (std::find(excluded.begin(), excluded.end(), key) != excluded.end()) return false;
  if (std::find(extra.begin(), extra.end(), key) != extra.end()) return true;
  return (spec.commands & commands) != 0;
}

void value_error(const OptionScope& scope, const std::string& message) {
  throw py::value_error(scope.function + "(): " + message);
}

namespace {

std::string valid_keys(const OptionScope& scope) {
  std::string keys;
  for (const SettingSpec& s : settings_schema())
    if (scope.takes(s)) keys += (keys.empty() ? "" : ", ") + std::string(s.key);
  return keys;
}

// True for NumPy's scalar types of `kind` ("bool_", "integer", "floating"), without importing
// NumPy when it is not loaded (then no value can be one).
bool is_numpy(const py::handle& v, const char* kind) {
  py::object modules = py::module_::import("sys").attr("modules");
  if (!modules.contains("numpy")) return false;
  return py::isinstance(v, modules["numpy"].attr(kind));
}

// A value as the schema's text: str and os.PathLike as they are, integers in decimal (Python's
// and NumPy's: anything with __index__), floats by their shortest text (Python's repr of the
// value; NumPy's own for its float32/float16, the digits it shows). bool is refused: no
// setting is a yes/no switch.
std::string option_text(const OptionScope& scope, const std::string& key, const py::handle& v) {
  if (py::isinstance<py::bool_>(v) || is_numpy(v, "bool_"))
    throw py::type_error(scope.function + "(): " + key +
                         ": expected a string or a number, got a bool");
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::int_>(v) || is_numpy(v, "integer")) {
    PyObject* whole = PyNumber_Index(v.ptr());
    if (!whole) throw py::error_already_set();
    return py::str(py::reinterpret_steal<py::object>(whole)).cast<std::string>();
  }
  // float subclasses (numpy.float64) by the value, not by their own repr ("np.float64(0.5)").
  if (py::isinstance<py::float_>(v))
    return py::repr(py::float_(PyFloat_AsDouble(v.ptr()))).cast<std::string>();
  if (is_numpy(v, "floating")) return py::str(v).cast<std::string>();
  if (py::hasattr(v, "__fspath__")) {
    py::object path = py::module_::import("os").attr("fspath")(v);
    if (py::isinstance<py::str>(path)) return path.cast<std::string>();
  }
  throw py::type_error(scope.function + "(): " + key + ": expected a string or a number, got " +
                       py::str(py::type::of(v).attr("__name__")).cast<std::string>());
}

}  // namespace

Settings read_options(const py::kwargs& options, const OptionScope& scope,
                      std::vector<std::string>* given) {
  Settings settings;
  for (const auto& [k, v] : options) {
    const std::string key = py::str(k).cast<std::string>();
    const SettingSpec* spec = find_setting(key);
    if (!spec || !scope.takes(*spec))
      value_error(scope, "unknown option " + quote(key) + " (valid: " + valid_keys(scope) + ")");
    if (v.is_none()) continue;
    const std::string text = option_text(scope, key, v);
    try {
      apply_setting(settings, *spec, text, key);
    } catch (const Error& e) {
      value_error(scope, e.what());
    }
    if (given) given->push_back(key);
  }
  return settings;
}

std::string options_doc(const OptionScope& scope) {
  std::string doc;
  const Settings defaults;
  for (const SettingSpec& s : settings_schema()) {
    if (!scope.takes(s)) continue;
    std::string def(s.default_text);
    if (def.empty()) def = s.format(defaults);
    doc += "    " + std::string(s.key) + ": " + s.help +
           " (default: " + (def.empty() ? "none" : def) + ").\n";
  }
  return doc;
}

}  // namespace spectralize::python
