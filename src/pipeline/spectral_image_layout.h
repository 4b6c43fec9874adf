#pragma once
// The layout of a written spectral image (docs/DESIGN.md §7): which channels hold the bands,
// the RGB previews and alpha, with which names and attributes. The spectral OpenEXR layout of
// Fichet, Pacanowski & Wilkie (JCGT 2021) with R, G, B previews is the implementation; the pixel
// kernel only needs the channel offsets, so other layouts can be added beside it.

#include <OpenImageIO/imageio.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "colour/colour_space.h"
#include "settings/settings.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

class SpectralImageLayout {
 public:
  virtual ~SpectralImageLayout() = default;
  /// Size, windows, channels, sample type, tiling and attributes of the written image.
  /// Cost: O(1).
  virtual const OIIO::ImageSpec& spec() const = 0;
  /// The first band channel: the bands follow contiguously, by increasing wavelength. Cost: O(1).
  virtual int band_channel() const = 0;
  /// The R of the R, G, B preview (G and B follow), or -1 without previews. Cost: O(1).
  virtual int preview_channel() const = 0;
  /// The alpha channel, or -1. Cost: O(1).
  virtual int alpha_channel() const = 0;
  /// The colour space of the previews. Cost: O(1).
  virtual const std::string& preview_colorspace() const = 0;
};

/// What a layout is made from.
struct LayoutRequest {
  const OIIO::ImageSpec& input;  // windows and descriptive metadata to carry over
  bool alpha = false;            // the input has alpha
  // Sample type, compression, tiling; the settings written, as resolved for the file (its
  // colorspace and preview_colorspace are the spaces decided for it).
  const Settings& settings;
  std::string input_colorspace;
  std::string preview_colorspace;
  const ColourSpaces& spaces;                                // to tag the previews
  std::string date_time;                                     // EXIF DateTime
  std::map<std::string, std::string> attributes = {};        // more string attributes to record
  std::vector<std::pair<std::string, double>> numbers = {};  // and double ones
};

/// The spectral OpenEXR layout: R, G, B previews (tagged with their colour space), A when the
/// input has alpha, then "S0.<nm>nm" (emission) or "T.<nm>nm" (reflectance) bands;
/// spectralLayoutVersion, emissiveUnits for emission, the settings as spectralize:*
/// attributes, the input's descriptive metadata. Cost: O(channels + attributes).
std::unique_ptr<SpectralImageLayout> spectral_exr_layout(const LayoutRequest& request);

/// Bare spectra: the bands only, as floats, one "pixel" per colour (arrays of colours, e.g.
/// the Python module's spectra()). Cost: O(bands).
std::unique_ptr<SpectralImageLayout> bare_spectra_layout(const SpectralizerSettings& settings);

}  // namespace spectralize
