#pragma once
// Validation of flag values shared by the commands: every mistake becomes a UsageError whose
// message names the flag and the value.

#include <string>
#include <vector>

#include "core/error.h"
#include "core/spectralizer.h"
#include "io/colour_space.h"
#include "tool/options.h"

namespace spectralize::tool {

/// Runs `fn`, turning the core's configuration errors into usage errors naming the flag.
/// Cost: that of fn.
template <typename Fn>
auto flag_value(const char* flag, Fn&& fn) {
  try {
    return fn();
  } catch (const Error& e) {
    throw UsageError{std::string(flag) + ": " + e.what()};
  }
}

/// The grid, observer, illuminant, filter, model and emission basis of the options (mode left
/// to the caller).
/// Cost: O(1).
SpectralizerSettings spectral_settings(const Options& options);

/// A colour given as "R,G,B".
struct Rgb {
  double r, g, b;
  std::string text;  // as given
};

/// Parses --color's "R,G,B": three finite numbers (spaces around them allowed); UsageError
/// naming the value otherwise. Cost: O(length).
Rgb parse_rgb(const std::string& text);

/// What every --color command needs: the settings (mode defaulting to emission), the parsed
/// colours, the config and the transform of --colorspace to XYZ. UsageError for a mistake.
/// Cost: parsing the config, ~ms.
struct ColourInputs {
  SpectralizerSettings settings;
  std::vector<Rgb> colours;
  ColourSpaces spaces;
  ColourTransform to_xyz;
};
ColourInputs colour_inputs(const Options& options);

/// The spectrum of one --color value; warns on stderr when it was out of gamut and mapped,
/// reports an error and sets `status` to kExitFailure when it is invalid. Cost: one solve.
SpectrumResult spectralize_colour(const Spectralizer& spectralizer, const ColourTransform& to_xyz,
                                  const Rgb& colour, int& status);

/// The OCIO config of --config (a usage error if unreadable), else $OCIO or the shipped one.
/// Cost: parsing the config, ~ms.
ColourSpaces load_config(const Options& options);

/// Parses a whole number in [min, max] given to `flag`. Cost: O(length).
int parse_int_flag(const char* flag, const std::string& text, int min, int max);

}  // namespace spectralize::tool
