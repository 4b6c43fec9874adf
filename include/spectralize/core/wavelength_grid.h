#pragma once
// The sampling grid of a spectrum: lambda_i = start + i*step, i = 0..N-1 (docs/DESIGN.md §3).

#include <cstddef>
#include <string>
#include <string_view>

namespace spectralize {

class WavelengthGrid {
 public:
  static constexpr double kMinNm = 360.0;    // the CIE 1 nm tables start here
  static constexpr double kMaxNm = 830.0;    // ... and end here
  static constexpr double kMinStepNm = 0.5;  // finer grids gain nothing on 1 nm tables

  /// The default grid, 380:780:5 (81 samples). Cost: O(1).
  WavelengthGrid() : WavelengthGrid(380.0, 780.0, 5.0) {}
  /// A grid from start to end inclusive; throws Error if empty, reversed, off the 1 nm tables,
  /// too fine, or if end is not start + k*step. Cost: O(1).
  WavelengthGrid(double start_nm, double end_nm, double step_nm);
  /// Parses "start:end:step" in nm (e.g. "380:780:5"); throws Error naming the problem. Cost:
  /// O(len).
  static WavelengthGrid parse(std::string_view spec);

  /// Number of samples N. Cost: O(1).
  std::size_t size() const { return count_; }
  /// Wavelength of sample i in nm. Cost: O(1).
  double operator[](std::size_t i) const { return start_ + static_cast<double>(i) * step_; }
  double start() const { return start_; }
  double end() const { return (*this)[count_ - 1]; }
  double step() const { return step_; }
  /// "380:780:5" form, parseable by parse(). Cost: O(1).
  std::string to_string() const;
  friend bool operator==(const WavelengthGrid&, const WavelengthGrid&) = default;

 private:
  double start_, step_;
  std::size_t count_;
};

}  // namespace spectralize
