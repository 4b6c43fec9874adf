#pragma once
// Spectral OpenEXR (the layout of docs/DESIGN.md §7, written by any tool) back to RGB:
// emissive S0 channels integrated with the observer, reflective T channels under an
// illuminant, on the file's own wavelengths by the reference integration (docs/DESIGN.md §3),
// then converted by OCIO.

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "settings/settings.h"
#include "spectralize/core/sample_weights.h"

namespace spectralize {

/// Where the spectral data of a file is.
struct SpectralLayoutInfo {
  bool emissive = true;               // S0 channels (else T)
  std::vector<int> band_channels;     // channel index of each band, by increasing wavelength
  std::vector<double> wavelengths;    // nm, increasing
  int alpha = -1;                     // the "A" channel, if any
  bool polarised = false;             // S1..S3 present (ignored: S0 is the intensity)
  std::vector<std::string> unparsed;  // channels that look spectral but do not parse (ignored)
};

/// Finds and checks the spectral channels of a spec: sorted by wavelength whatever their order
/// in the file; refuses (Error naming `file`) files without spectral channels, with both S0 and
/// T channels, with S1..S3 but no S0, with bispectral (fluorescent) T.<in>.<out> channels, with
/// two channels at one wavelength, with one band, or with no band inside 360-830 nm.
/// Cost: O(channels log channels).
SpectralLayoutInfo analyse_spectral_layout(const OIIO::ImageSpec& spec, const std::string& file);

/// The layout of spectra given as arrays: sample i (channel i) at wavelengths[i] nm. Refuses
/// (Error starting with `where`) non-finite or not strictly increasing wavelengths, fewer than
/// two, or none inside 360-830 nm. Cost: O(N).
SpectralLayoutInfo spectral_layout_of_samples(const std::vector<double>& wavelengths, bool emissive,
                                              const std::string& where);

/// What RgbFromSpectral counted.
struct RgbCounts {
  std::uint64_t invalid = 0;         // pixels with NaN or infinite samples (taken as 0)
  std::uint64_t half_overflow = 0;   // half output: pixels with RGB beyond 65504 (clamped)
  std::uint64_t float_overflow = 0;  // float output: pixels with RGB beyond float's range
  std::uint64_t clipped = 0;         // integer output: pixels with a value more than half a code
                                     // value outside 0..1 (clipped: a code lost)
};

class RgbFromSpectral {
 public:
  /// Prepares the integration weights (settings.spectral.observer; reflective files under
  /// settings.spectral.illuminant) and the OCIO conversion to settings.colorspace (already
  /// resolved). Throws Error. Cost: O(N).
  RgbFromSpectral(const SpectralLayoutInfo& layout, const Settings& settings,
                  const ColourSpaces& spaces);

  /// Output channels: 3, or 4 with alpha. Cost: O(1).
  int output_channels() const { return layout_.alpha >= 0 ? 4 : 3; }
  /// n pixels of in_nch float channels to n pixels of RGB(A). Emission: XYZ = W . S0.
  /// Reflectance: XYZ of rho under the illuminant relative to its white (rho == 1 gives the
  /// D65 white, so RGB (1, 1, 1): the paper's eq. 6, the inverse of spectralize's white
  /// balance; with as-lit the reflected light itself). Non-finite samples count as 0; values
  /// are clamped to what `type` stores (HALF's range; 0..1 for integers), and counted. Returns
  /// what it counted. Thread-safe. Cost: O(n x bands).
  RgbCounts convert(const float* in, int in_nch, std::size_t n, float* out,
                    OIIO::TypeDesc type) const;

 private:
  SpectralLayoutInfo layout_;
  std::vector<float> wx_, wy_, wz_;
  float balance_[3] = {1, 1, 1};
  ColourTransform from_xyz_;
};

/// The sample type --to-rgb writes: uint8/uint16 (settings.integer_bits) or HALF/FLOAT.
/// Cost: O(1).
OIIO::TypeDesc rgb_sample_type(const Settings& settings);

/// The colour space of the RGB --to-rgb writes: settings.colorspace, or the space the OCIO
/// display's view ends in ("" when the config names none). Cost: O(1).
std::string rgb_output_space(const Settings& settings, const ColourSpaces& spaces);

/// The spec of RGB(A) written from a spectral `source` (its windows), tagged with its colour
/// space (or display), with the settings that made it; used by --to-rgb and the plugin.
/// Cost: O(attributes).
OIIO::ImageSpec rgb_output_spec(const OIIO::ImageSpec& source, const SpectralLayoutInfo& layout,
                                const Settings& settings, const ColourSpaces& spaces,
                                const std::string& date_time);

}  // namespace spectralize
