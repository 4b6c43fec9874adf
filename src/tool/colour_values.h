#pragma once
// The --color values: parsed strictly, planned against the config and turned into spectra,
// with what is said of a colour out of gamut or invalid.

#include <memory>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "core/tables/spectral_table.h"
#include "spectralize/core/spectralizer.h"
#include "tool/console.h"
#include "tool/options.h"

namespace spectralize::tool {

/// A colour given as "R,G,B".
struct Rgb {
  double r, g, b;
  std::string text;  // as given
};

/// Parses --color's "R,G,B": three finite numbers (spaces around them allowed); UsageError
/// naming the value and the slip otherwise. Cost: O(length).
Rgb parse_rgb(const std::string& text);

/// What every --color command needs: the spectralizer settings (mode auto meaning emission),
/// the parsed colours, the config, the transform of --colorspace (default: the config's
/// scene_linear role) to XYZ and the RGB frame of its exact table (pipeline/render_table.h).
/// UsageError for a mistake. Cost: parsing the config, ~ms.
struct ColourInputs {
  SpectralizerSettings settings;
  std::vector<Rgb> colours;
  std::shared_ptr<const ColourSpaces> spaces;
  ColourTransform to_xyz;
  Mat3 frame;
};
ColourInputs colour_inputs(const Options& options);

/// The spectrum of one --color value: the exact table's (`table`; the spectra images and a
/// renderer's table file give) or, with `table` null (--method exact), a direct solve with the
/// model's details. Warns on stderr when it was out of gamut and mapped (and says when a
/// reflectance was brighter than white), reports an error and sets `status` to kExitFailure
/// when it is invalid. Cost: a cell's node solves on first use (~40 us each), or one solve.
SpectrumResult spectralize_colour(const Spectralizer& spectralizer, SpectralTable* table,
                                  const ColourTransform& to_xyz, const Rgb& colour, int& status);

}  // namespace spectralize::tool
