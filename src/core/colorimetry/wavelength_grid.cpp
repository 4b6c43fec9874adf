#include "spectralize/core/wavelength_grid.h"

#include <charconv>
#include <cmath>
#include <string>

#include "core/decimal_number.h"
#include "spectralize/core/error.h"

namespace spectralize {

namespace {

std::string number(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

WavelengthGrid::WavelengthGrid(double start_nm, double end_nm, double step_nm)
    : start_(start_nm), step_(step_nm), count_(0) {
  if (!std::isfinite(start_nm) || !std::isfinite(end_nm) || !std::isfinite(step_nm))
    throw Error("wavelength grid: values must be finite numbers");
  if (step_nm <= 0) throw Error("wavelength grid: step must be positive, got " + number(step_nm));
  if (step_nm < kMinStepNm)
    throw Error("wavelength grid: step " + number(step_nm) + " nm is below the minimum of 0.5 nm");
  if (end_nm < start_nm)
    throw Error("wavelength grid: end " + number(end_nm) + " nm is below start " +
                number(start_nm) + " nm (reversed grid)");
  if (start_nm < kMinNm || end_nm > kMaxNm)
    throw Error("wavelength grid: " + number(start_nm) + ".." + number(end_nm) +
                " nm leaves the CIE tables' range 360..830 nm");
  // The grid must land on `end`: a silently shortened grid would change the colour.
  double intervals = (end_nm - start_nm) / step_nm;
  double rounded = std::round(intervals);
  if (std::abs(intervals - rounded) > 1e-6)
    throw Error("wavelength grid: (end - start) = " + number(end_nm - start_nm) +
                " nm is not a whole number of " + number(step_nm) + " nm steps");
  count_ = static_cast<std::size_t>(rounded) + 1;
  if (count_ < 3)
    throw Error("wavelength grid: needs at least 3 samples to match 3 tristimulus values, got " +
                std::to_string(count_));
}

WavelengthGrid WavelengthGrid::parse(std::string_view spec) {
  double v[3];
  std::string_view rest = spec;
  for (int i = 0; i < 3; ++i) {
    std::size_t colon = rest.find(':');
    std::string_view part = (i < 2) ? rest.substr(0, colon) : rest;
    if ((i < 2 && colon == std::string_view::npos) || (i == 2 && part.find(':') != part.npos))
      throw Error("wavelength grid " + quote(spec) + ": expected start:end:step in nm");
    try {
      v[i] = decimal_number(part);
    } catch (const Error& e) {
      throw Error("wavelength grid " + quote(spec) + ": " + e.what());
    }
    if (i < 2) rest = rest.substr(colon + 1);
  }
  try {
    return WavelengthGrid(v[0], v[1], v[2]);
  } catch (const Error& e) {
    // "wavelength grid: why" -> "wavelength grid '380:781:5': why", naming what was given.
    const std::string why = e.what();
    throw Error("wavelength grid " + quote(spec) + why.substr(why.find(':')));
  }
}

std::string WavelengthGrid::to_string() const {
  return number(start_) + ":" + number(end()) + ":" + number(step_);
}

}  // namespace spectralize
