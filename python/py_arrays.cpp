#include "py_arrays.h"

#include <cmath>
#include <cstdint>
#include <utility>

namespace py = pybind11;

namespace spectralize::python {

namespace {

std::string shape_text(const std::vector<py::ssize_t>& shape) {
  std::string t = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) t += (i ? ", " : "") + std::to_string(shape[i]);
  return t + (shape.size() == 1 ? ",)" : ")");
}

// The index tuple of flat element `flat` of a C-ordered array of `shape`.
std::string index_text(std::size_t flat, const std::vector<py::ssize_t>& shape) {
  std::vector<py::ssize_t> index(shape.size());
  for (std::size_t a = shape.size(); a-- > 0;) {
    index[a] = static_cast<py::ssize_t>(flat % static_cast<std::size_t>(shape[a]));
    flat /= static_cast<std::size_t>(shape[a]);
  }
  return shape_text(index);
}

}  // namespace

FloatArray read_float_array(const py::handle& object, const std::string& name, std::size_t last,
                            bool nonfinite_allowed) {
  py::array any = py::module_::import("numpy").attr("asarray")(object);
  const char kind = any.dtype().kind();
  if (kind != 'f')
    throw py::type_error(
        name + ": dtype " + py::str(any.dtype()).cast<std::string>() +
        " is not floating point; give linear float values (integer data is encoded: convert "
        "it to float and name its colour space)");
  FloatArray a;
  a.shape.assign(any.shape(), any.shape() + any.ndim());
  if (any.ndim() == 0)
    throw py::value_error(name + ": a scalar; expected an array whose last axis has " +
                          (last ? std::to_string(last) + " values" : "the samples"));
  const auto n_last = static_cast<std::size_t>(a.shape.back());
  if ((last && n_last != last) || (!last && n_last == 0))
    throw py::value_error(name + ": shape " + shape_text(a.shape) + ": the last axis must have " +
                          (last ? std::to_string(last) + " values" + (last == 3 ? " (R, G, B)" : "")
                                : std::string("at least one value")));
  // C-contiguous float32 whatever the strides and dtype (a copy only where needed).
  a.array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(any);
  if (!a.array) throw py::error_already_set();
  a.data = a.array.data();
  a.last = n_last;
  const auto size = static_cast<std::size_t>(a.array.size());
  a.rows = size / n_last;
  if (nonfinite_allowed) return a;
  std::size_t bad = 0, first = 0;
  for (std::size_t i = 0; i < size; ++i)
    if (!std::isfinite(a.data[i]) && bad++ == 0) first = i;
  if (bad)
    throw py::value_error(
        name + ": " + std::to_string(bad) + (bad == 1 ? " value is" : " values are") +
        " NaN or infinite (or beyond float32's range), the first at " + index_text(first, a.shape) +
        "; replace them first (e.g. numpy.nan_to_num)");
  return a;
}

std::vector<double> read_wavelength_array(const py::handle& object, const std::string& name) {
  py::array any = py::module_::import("numpy").attr("asarray")(object);
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(name + ": dtype " + py::str(any.dtype()).cast<std::string>() +
                         " is not a number; give the wavelengths in nm");
  if (any.ndim() != 1)
    throw py::value_error(name + ": expected a 1-D array, got " + std::to_string(any.ndim()) +
                          " axes");
  // float64 whatever was given: [500, 500.00001] stays strictly increasing.
  auto nm = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(any);
  if (!nm) throw py::error_already_set();
  std::vector<double> out(nm.data(), nm.data() + nm.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      throw py::value_error(name + ": value " + std::to_string(i) + " is NaN or infinite");
  return out;
}

bool may_share_memory(const py::array& a, const py::array& b) {
  // The byte range each array's elements span, whatever the sign of its strides.
  auto span = [](const py::array& x) {
    auto lo = reinterpret_cast<std::intptr_t>(x.data());
    auto hi = lo;
    for (py::ssize_t d = 0; d < x.ndim(); ++d) {
      if (x.shape(d) == 0) return std::pair<std::intptr_t, std::intptr_t>{0, 0};
      const auto reach = static_cast<std::intptr_t>(x.strides(d)) * (x.shape(d) - 1);
      (reach < 0 ? lo : hi) += reach;
    }
    return std::pair<std::intptr_t, std::intptr_t>{lo,
                                                   hi + static_cast<std::intptr_t>(x.itemsize())};
  };
  const auto [a0, a1] = span(a);
  const auto [b0, b1] = span(b);
  return a0 < a1 && b0 < b1 && a0 < b1 && b0 < a1;
}

py::array_t<float> new_float_array(const std::vector<py::ssize_t>& shape, std::size_t last) {
  std::vector<py::ssize_t> s = shape;
  s.back() = static_cast<py::ssize_t>(last);
  return py::array_t<float>(s);
}

}  // namespace spectralize::python
