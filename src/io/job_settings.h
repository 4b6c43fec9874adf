#pragma once
// The settings of a file job, checked and resolved before any work (docs/DESIGN.md §8), the
// same for every front end: the CLI names options as flags ("--colorspace", "-o"), the Python
// module as keywords ("colorspace", "output"). Each problem throws Error naming the option.

#include <string>

#include "io/settings.h"

namespace spectralize {

/// How a front end spells its options in messages.
struct OptionNames {
  std::string prefix;  // before a setting's key: "--" (CLI) or "" (Python)
  std::string output;  // the output's name: "-o" or "output"
  /// A setting's name as this front end spells it: its flag on the command line
  /// ("--preview-colorspace"), else prefix + key. Cost: O(settings).
  std::string operator()(const std::string& key) const {
    if (prefix == "--")
      if (const SettingSpec* spec = find_setting(key)) return std::string(spec->flag);
    return prefix + key;
  }
};

/// RGB -> spectral OpenEXR: a .exr output, half or float samples, the config loads, the colour
/// space (if given) exists; returned resolved. Cost: the config's parse.
Settings checked_image_settings(Settings settings, const std::string& output,
                                const OptionNames& names);

/// Spectral -> RGB: an output type OpenImageIO writes; colorspace or display (not both), view
/// only with display, each existing; files that store integers (PNG, TIFF, JPEG) get 8-bit
/// samples unless `format_given` and the config's texture space by default, float files its
/// scene-linear space. Returned resolved. Cost: the config's parse, an OCIO processor.
Settings checked_to_rgb_settings(Settings settings, const std::string& output, bool format_given,
                                 const OptionNames& names);

/// Ingest: half or float samples, the config loads, the colour space (if given) exists;
/// returned resolved. Cost: the config's parse.
Settings checked_ingest_settings(Settings settings, const OptionNames& names);

}  // namespace spectralize
