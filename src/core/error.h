#pragma once
// The core library's one error model: configuration mistakes (bad grid, unknown observer or
// illuminant, malformed filter) throw spectralize::Error; per-colour problems (out of gamut,
// NaN, negative luminance) never throw and are reported in SpectrumResult::status instead.

#include <stdexcept>
#include <string>

namespace spectralize {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace spectralize
