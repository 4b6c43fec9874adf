#pragma once
// The spectral OpenEXR layout of Fichet, Pacanowski & Wilkie (JCGT 2021), docs/DESIGN.md §7:
// channel names like "S0.550,000000nm" (emissive, Stokes 0..3) or "T.550,000000nm" (reflective),
// with a comma as decimal separator because '.' separates EXR layers.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

/// Names and values of the layout's attributes.
inline constexpr const char* kLayoutVersionAttr = "spectralLayoutVersion";
inline constexpr const char* kLayoutVersion = "1.0";
inline constexpr const char* kEmissiveUnitsAttr = "emissiveUnits";
inline constexpr const char* kEmissiveUnits = "W.m^-2.sr^-1";

/// A parsed spectral channel name.
struct SpectralChannel {
  enum class Kind { emissive, reflective };
  Kind kind = Kind::emissive;
  int stokes = 0;            // emissive: Stokes component 0..3 (S0 is the intensity)
  double wavelength_nm = 0;  // converted from the name's unit (nm, um, Hz, ...)
};

/// The channel name of a sample: "S0.380,000000nm" (emissive) or "T.380,000000nm" (reflective),
/// six decimals as the reference implementation writes, independent of the locale. Cost: O(1).
std::string spectral_channel_name(SpectralChannel::Kind kind, double wavelength_nm, int stokes = 0);

/// Parses a channel name with the layout's reference regex
/// ^((S([0-3]))|T)\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$
/// and converts the value to nm; nullopt for any other channel (R, G, B, A, ...).
/// Cost: O(length).
std::optional<SpectralChannel> parse_spectral_channel(std::string_view name);

}  // namespace spectralize
