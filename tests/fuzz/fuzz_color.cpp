// libFuzzer target: the --color "R,G,B" parser, then the exact spectralizer on what it accepts
// (10 nm, both modes, both models): parsed values are finite, results never crash, spectra are
// finite and non-negative (reflectances <= 1), and exact to the float bar of docs/DESIGN.md §3
// (1e-5 relative). Fuzzing found reflectances of dark purples next to the solid's boundary where
// the bounded projection stops at ~1e-5 (they say so in their message): hence 1e-5 here, not double
// precision.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "spectralize/core/spectralizer.h"
#include "tool/colour_values.h"

using namespace spectralize;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // Both modes, both models (the smooth model's quadratic programme meets the same inputs).
  auto make = [](Mode mode, const char* model) {
    SpectralizerSettings s;
    s.grid = WavelengthGrid(380, 780, 10);
    s.mode = mode;
    s.model = model;
    return Spectralizer(s);
  };
  static const Spectralizer emission = make(Mode::emission, "paper");
  static const Spectralizer reflectance = make(Mode::reflectance, "paper");
  static const Spectralizer smooth_emission = make(Mode::emission, "smooth");
  static const Spectralizer smooth_reflectance = make(Mode::reflectance, "smooth");
  tool::Rgb rgb;
  try {
    rgb = tool::parse_rgb(text);
  } catch (const tool::UsageError&) {
    return 0;
  }
  if (!std::isfinite(rgb.r) || !std::isfinite(rgb.g) || !std::isfinite(rgb.b)) __builtin_trap();
  const Xyz xyz{rgb.r, rgb.g, rgb.b};  // taken as XYZ: covers every direction
  for (const Spectralizer* sp : {&emission, &reflectance, &smooth_emission, &smooth_reflectance}) {
    SpectrumResult r = sp->spectralize(xyz);
    const double upper = sp->settings().mode == Mode::reflectance ? 1.0 : INFINITY;
    for (double v : r.values)
      if (!(v >= 0) || !std::isfinite(v) || v > upper) __builtin_trap();
    if ((r.status == Outcome::exact || out_of_gamut(r.status)) && r.target.max_abs() > 1e-300 &&
        r.target.max_abs() < 1e300 && !(r.relative_error <= 1e-5))
      __builtin_trap();
  }
  return 0;
}
