#pragma once
// The settings of a file job, checked and resolved before any work (docs/DESIGN.md §8), the
// same for every front end: the CLI names options as flags ("--colorspace", "-o"), the Python
// module as keywords ("colorspace", "output"). Each problem throws Error naming the option.

#include <string>

#include "settings/settings.h"

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

/// RGB -> spectral OpenEXR: a .exr output, half or float samples, a compression and tiles
/// OpenEXR takes (imagefile/output_formats.h), the config loads, the colour space (if given)
/// exists; returned resolved. Cost: the config's parse.
Settings checked_image_settings(Settings settings, const std::string& output,
                                const OptionNames& names);

/// Spectral -> RGB: an output format of the table (imagefile/output_formats.h) that stores the
/// sample type, compression and tiles asked; colorspace or display (not both), view only with
/// display, each existing. Without `format_given`, formats that store integers (PNG, TIFF, JPEG,
/// ...) get 8-bit samples and the config's texture space, float formats their scene-linear space;
/// without `compression_given` the format's own default compression. Returned resolved.
/// Cost: the config's parse, an OCIO processor.
Settings checked_to_rgb_settings(Settings settings, const std::string& output, bool format_given,
                                 bool compression_given, const OptionNames& names);

/// Ingest: half or float samples, a compression and tiles OpenEXR takes, the config loads, the
/// colour space (if given) exists; returned resolved. Cost: the config's parse.
Settings checked_ingest_settings(Settings settings, const OptionNames& names);

}  // namespace spectralize
