#pragma once
// NumPy arguments: checked (floating point, the right last axis, finite) and copied into
// contiguous float32, with messages that name the argument.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace spectralize::python {

/// A checked array argument as C-ordered float32 (the caller's own memory when it already is).
struct FloatArray {
  pybind11::array_t<float> array;        // keeps `data` alive
  const float* data = nullptr;           // C order
  std::vector<pybind11::ssize_t> shape;  // as given
  std::size_t rows = 0;                  // product of all axes but the last
  std::size_t last = 0;                  // the last axis' size
};

/// Reads `object` (an ndarray, or anything numpy.asarray takes) named `name` in messages
/// ("spectra(): rgb: ..."): a floating-point dtype (else TypeError; integers are encoded data),
/// at least one axis, a last axis of `last` (0: any, at least 1) (else ValueError), every value
/// finite in float32 unless `nonfinite_allowed` (else ValueError with the count and the first
/// index). Any strides and dtypes are copied into C-ordered float32; float32 C-ordered arrays
/// are used in place. Running out of memory raises MemoryError, as NumPy does. Cost: O(size).
FloatArray read_float_array(const pybind11::handle& object, const std::string& name,
                            std::size_t last, bool nonfinite_allowed = false);

/// Reads a 1-D array of wavelengths in nm (any integer or floating dtype) as float64, every
/// value kept as given (never rounded to float32); TypeError for other dtypes, ValueError for
/// another number of axes or non-finite values, naming `name`. Cost: O(size).
std::vector<double> read_wavelength_array(const pybind11::handle& object, const std::string& name);

/// True when the memory spanned by `a` and by `b` overlaps (numpy.may_share_memory's bounds
/// test, over any strides): writing one may change the other. Cost: O(axes).
bool may_share_memory(const pybind11::array& a, const pybind11::array& b);

/// A new float32 array of `shape` whose last axis is replaced by `last`. Cost: O(size).
pybind11::array_t<float> new_float_array(const std::vector<pybind11::ssize_t>& shape,
                                         std::size_t last);

}  // namespace spectralize::python
