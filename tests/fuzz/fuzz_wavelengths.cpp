// libFuzzer target: the --wavelengths "START:END:STEP" parser. Accepted grids are inside
// 360..830 nm, step >= 0.5, at least 3 samples, and round-trip through to_string().
#include <cstddef>
#include <cstdint>
#include <string>

#include "spectralize/core/error.h"
#include "spectralize/core/wavelength_grid.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    spectralize::WavelengthGrid g = spectralize::WavelengthGrid::parse(text);
    if (g.size() < 3 || g.start() < 360 || g.end() > 830 + 1e-6 || g.step() < 0.5) __builtin_trap();
    if (!(spectralize::WavelengthGrid::parse(g.to_string()) == g)) __builtin_trap();
  } catch (const spectralize::Error&) {
  }
  return 0;
}
