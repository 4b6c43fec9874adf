#pragma once
// What a job resolved before any pixel (docs/DESIGN.md §8, §10), the same for every front end:
// the settings checked against the output and the config, the config parsed once, the mode
// and colour spaces with their reasons, the channels and the layout's channel count, and how
// the caller spells its options. One planning function per direction (to spectral, to RGB),
// plus the colour jobs without an image; they are the only code that loads the config for a
// job and resolves its mode. The CLI names options as flags ("--colorspace", "-o"), the
// Python module as keywords ("colorspace", "output"). Each problem of the settings throws
// Error naming the option.

#include <OpenImageIO/imageio.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "pipeline/rgb_from_spectral.h"
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

/// What a job resolved. A plan made by a planning function holds the checked settings and the
/// config; planned_input() then decides one input file for it.
struct JobPlan {
  Settings settings;  // checked; after planned_input, as resolved for the file (its header's)
  OptionNames names{"--", "-o"};               // the caller's spellings, for messages
  std::shared_ptr<const ColourSpaces> spaces;  // the config, parsed once per job (or batch)
  bool to_rgb = false;                         // the direction
  // The spaces the options name, resolved once (settings hold their canonical names); for
  // colours without an image, the colour space as defaulted too.
  NamedSpace colorspace, preview_colorspace;
  std::vector<std::string> warnings;  // said while planning, for the caller to show (each use)
  // After planned_input:
  std::string input;                   // the file decided ("" before)
  InputInterpretation interpretation;  // to spectral: channels, colour space, mode, reasons
  SpectralLayoutInfo spectral;         // to RGB: the input's bands, alpha, kind
  int output_channels = 0;             // channels of the written image
  /// The loaded config. Cost: O(1).
  const ColourSpaces& colour_spaces() const { return *spaces; }
  /// True once planned_input decided an input. Cost: O(1).
  bool decided() const { return !input.empty(); }
};

/// What a colour job without an image is about: the mode's default differs.
enum class ColourSubject {
  colours,  // --color, spectralize.spectra(): float values, "auto" is light (as float data)
  spectra,  // spectra to RGB (spectralize.to_rgb()): "auto" is light
  table,    // a render-time table: "auto" is a surface (textures)
};

/// RGB -> spectral OpenEXR: a .exr output (`output` "" for a batch's outputs), half or float
/// samples, a compression and tiles OpenEXR takes (imagefile/output_formats.h), the config
/// loads, the colour space and preview space (if given) exist. Cost: the config's parse (once
/// per process for the same file: colour/colour_space.h).
JobPlan plan_to_spectral(Settings settings, const std::string& output, const OptionNames& names);

/// Resolves the spaces `plan.settings` names (colorspace, preview_colorspace: names, aliases,
/// roles or interop IDs) into the plan's NamedSpace records, the settings keeping the canonical
/// names; throws Error as ColourSpaces::named(), naming the option. The planning functions call
/// it; a batch calls it again for a file whose list line names its own. Cost: facts() of each.
void resolve_colour_spaces(JobPlan& plan);

/// Spectral -> RGB: an output format of the table (imagefile/output_formats.h) that stores the
/// sample type, compression and tiles asked; colorspace or display (not both), view only with
/// display, each existing. Without `format_given`, formats that store integers (PNG, TIFF, JPEG,
/// ...) get 8-bit samples and the config's texture space, float formats their scene-linear space;
/// without `compression_given` the format's own default compression. `output` "": a reader
/// presents the RGB (the plugin), no file format applies. Cost: the config's parse, an OCIO
/// processor.
JobPlan plan_to_rgb(Settings settings, const std::string& output, bool format_given,
                    bool compression_given, const OptionNames& names);

/// Colours without an image (`subject`): the config loads; the colour space resolved (given,
/// else the config's scene-linear space; a display for spectra to RGB); the mode resolved
/// (mode_of_subject). Colours in a data colour space are converted as an image's are, with
/// data_space_warning in the plan's warnings. Cost: the config's parse.
JobPlan plan_colours(Settings settings, ColourSubject subject, const OptionNames& names);

/// The mode of a colour job without an image: --mode if given, else the subject's default
/// (light for colours and spectra, a surface for a table). Cost: O(1).
Mode mode_of_subject(ModeChoice asked, ColourSubject subject);

/// `plan` decided for the input `input` of header `spec`. To spectral: channels, colour space,
/// data or colour, light or surface (classify/input_interpretation.h; `colour_decided` is a
/// caller's interpret_colour of this input and settings, completed with the mode), the
/// settings as resolved for the file and the layout's channel count; to RGB: the spectral
/// channels (analyse_spectral_layout) and the mode they hold. Throws Error naming the input.
/// Cost: OCIO look-ups, plus reading the image when no clue decides light or surface.
JobPlan planned_input(const JobPlan& plan, const std::string& input, const OIIO::ImageSpec& spec,
                      const InputInterpretation* colour_decided = nullptr);

/// The channels of the spectral OpenEXR written for `settings` (bands, R, G, B previews and
/// alpha when `alpha`): what readers of the input allocate per pixel. Cost: O(1).
int spectral_output_channels(const Settings& settings, bool alpha = true);

}  // namespace spectralize
