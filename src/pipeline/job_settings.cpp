#include "pipeline/job_settings.h"

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "imagefile/output_formats.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The spectral OpenEXR a job writes: its sample type, compression, tiles and the channels of
// `bands` bands with their previews (alpha, if the input has it, is checked by the job).
OutputRequest spectral_request(const Settings& s) {
  OutputRequest r;
  r.samples = s.half ? "half" : "float";
  r.compression = s.compression;
  r.tile_width = s.tile_width;
  r.tile_height = s.tile_height;
  r.channels = static_cast<int>(s.spectral.grid.size()) + 3;
  return r;
}

ColourSpaces load_config(const Settings& s, const OptionNames& names) {
  if (s.config.empty()) return ColourSpaces::load();
  try {
    return with_context(names("config"), [&] { return ColourSpaces::load(s.config); });
  } catch (const ConfigError& e) {
    throw ConfigError(names("config") + ": " + e.what());  // still the config's fault (exit 1)
  }
}

void resolve_colour_space(Settings& s, const ColourSpaces& spaces, const OptionNames& names) {
  if (!s.colorspace.empty())
    s.colorspace = with_context(names("colorspace"), [&] { return spaces.resolve(s.colorspace); });
  // Every colour space named by an option is checked before any work, the same way.
  if (!s.preview_colorspace.empty())
    s.preview_colorspace = with_context(names("preview_colorspace"),
                                        [&] { return spaces.resolve(s.preview_colorspace); });
}

}  // namespace

Settings checked_image_settings(Settings s, const std::string& output, const OptionNames& names) {
  if (lower_extension(output) != ".exr")
    throw Error(names.output + " '" + clip(output) +
                "': the output is a spectral OpenEXR file (.exr)");
  if (s.integer_bits != 0)
    throw Error(names("format") + " uint" + std::to_string(s.integer_bits) +
                ": a spectral OpenEXR stores half or float samples");
  check_output(output, spectral_request(s), names.prefix);
  resolve_colour_space(s, load_config(s, names), names);
  return s;
}

Settings checked_to_rgb_settings(Settings s, const std::string& output, bool format_given,
                                 bool compression_given, const OptionNames& names) {
  const OutputFormat* format = output_format_for(output);
  if (!format)
    throw Error(names.output + " '" + clip(output) +
                "': an image file OpenImageIO writes (.exr, .tif, .png, .jpg, .hdr, ...)");
  // Formats that store integers are display-referred: 8 bits unless a type is asked; the
  // others hold half (OpenEXR, the settings' default) or float (Radiance HDR).
  if (!format_given) {
    if (format->holds("uint8"))
      s.integer_bits = 8;
    else if (!format->holds("half"))
      s.half = false;
  }
  if (!compression_given) s.compression = std::string(format->default_compression);
  OutputRequest r;
  r.samples = s.integer_bits == 8    ? "uint8"
              : s.integer_bits == 16 ? "uint16"
              : s.half               ? "half"
                                     : "float";
  r.compression = s.compression;
  r.tile_width = s.tile_width;
  r.tile_height = s.tile_height;
  check_output(output, r, names.prefix);
  const ColourSpaces spaces = load_config(s, names);
  resolve_colour_space(s, spaces, names);
  if (!s.display.empty() && !s.colorspace.empty())
    throw Error("give " + names("colorspace") + " or " + names("display") + ", not both");
  if (!s.view.empty() && s.display.empty())
    throw Error(names("view") + " needs " + names("display"));
  if (!s.display.empty())
    with_context(names("display"), [&] { return spaces.display_from_xyz(s.display, s.view); });
  // Integer samples are display-referred: an encoded space by default; float ones linear.
  if (s.colorspace.empty() && s.display.empty())
    s.colorspace = default_colour_space(spaces, s.integer_bits == 0).first;
  return s;
}

Settings checked_ingest_settings(Settings s, const OptionNames& names) {
  if (s.integer_bits != 0)
    throw Error(names("format") + ": a spectral OpenEXR stores half or float samples");
  check_format(*output_format_named("openexr"), spectral_request(s),
               "the outputs (OpenEXR): ", names.prefix);
  resolve_colour_space(s, load_config(s, names), names);
  return s;
}

}  // namespace spectralize
