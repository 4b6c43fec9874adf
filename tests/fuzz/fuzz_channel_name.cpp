// libFuzzer target: spectral channel names ("S0.550,000000nm", "T.0,55um", ...). A parsed
// name has a positive finite wavelength, and our own names parse back to their wavelength.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "imagefile/spectral_channel.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name(reinterpret_cast<const char*>(data), size);
  auto c = spectralize::parse_spectral_channel(name);
  if (c && !(c->wavelength_nm > 0 && std::isfinite(c->wavelength_nm))) __builtin_trap();
  // Our names carry 6 decimals: the round trip holds where that resolves the value.
  if (c && c->wavelength_nm >= 1e-3 && c->wavelength_nm < 1e6) {
    auto again = spectralize::parse_spectral_channel(
        spectralize::spectral_channel_name(c->kind, c->wavelength_nm, c->stokes));
    if (!again ||
        std::abs(again->wavelength_nm - c->wavelength_nm) > 1e-6 * c->wavelength_nm + 1e-6 + 5e-7)
      __builtin_trap();
  }
  return 0;
}
