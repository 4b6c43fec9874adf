#pragma once
// Spectral OpenEXR (the layout of DESIGN §6, written by any tool) back to RGB: emissive S0
// channels integrated with the observer, reflective T channels under an illuminant, on the
// file's own wavelengths by the reference integration (DESIGN §3), then converted by OCIO.

#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>
#include <vector>

#include "core/sample_weights.h"
#include "io/colour_space.h"

namespace spectralize {

/// Where the spectral data of a file is.
struct SpectralLayoutInfo {
  bool emissive = true;             // S0 channels (else T)
  std::vector<int> band_channels;   // channel index of each band, by increasing wavelength
  std::vector<double> wavelengths;  // nm, increasing
  int alpha = -1;                   // the "A" channel, if any
  bool polarised = false;           // S1..S3 present (ignored: S0 is the intensity)
};

/// Finds and checks the spectral channels of a spec: sorted by wavelength whatever their order
/// in the file; refuses (Error naming `file`) files without spectral channels, with both S0 and
/// T channels, with S1..S3 but no S0, with two channels at one wavelength, or with one band.
/// Cost: O(channels log channels).
SpectralLayoutInfo analyse_spectral_layout(const OIIO::ImageSpec& spec, const std::string& file);

struct RgbSettings {
  std::string colorspace = "Linear Rec.709 (sRGB)";  // output space, any OCIO name
  std::string observer = "cie1931";
  std::string illuminant = "D65";  // reflective files: the light they are seen under
};

class RgbFromSpectral {
 public:
  /// Prepares the integration weights and the OCIO conversion. Throws Error. Cost: O(N).
  RgbFromSpectral(const SpectralLayoutInfo& layout, const RgbSettings& settings,
                  const ColourSpaces& spaces);

  /// Output channels: 3, or 4 with alpha. Cost: O(1).
  int output_channels() const { return layout_.alpha >= 0 ? 4 : 3; }
  /// n pixels of in_nch float channels to n pixels of RGB(A). Emission: XYZ = W . S0.
  /// Reflectance: XYZ of rho under the illuminant relative to its white (rho == 1 gives the
  /// D65 white, so RGB (1, 1, 1): the paper's eq. 6, the inverse of spectralize's white
  /// balance). Thread-safe. Cost: O(n x bands).
  void convert(const float* in, int in_nch, std::size_t n, float* out) const;

 private:
  SpectralLayoutInfo layout_;
  std::vector<float> wx_, wy_, wz_;
  float balance_[3] = {1, 1, 1};
  ColourTransform from_xyz_;
};

}  // namespace spectralize
