#include "io/job_settings.h"

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "core/error.h"
#include "io/colour_space.h"
#include "io/input_interpretation.h"
#include "io/safe_output.h"

namespace spectralize {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// A name whose extension OpenImageIO writes.
bool is_image_path(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) (void)OIIO::geterror();
  return out != nullptr;
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
  resolve_colour_space(s, load_config(s, names), names);
  return s;
}

Settings checked_to_rgb_settings(Settings s, const std::string& output, bool format_given,
                                 const OptionNames& names) {
  if (!is_image_path(output))
    throw Error(names.output + " '" + clip(output) +
                "': an image file OpenImageIO writes (.exr, .tif, .png, .jpg, .hdr, ...)");
  const ColourSpaces spaces = load_config(s, names);
  resolve_colour_space(s, spaces, names);
  if (!s.display.empty() && !s.colorspace.empty())
    throw Error("give " + names("colorspace") + " or " + names("display") + ", not both");
  if (!s.view.empty() && s.display.empty())
    throw Error(names("view") + " needs " + names("display"));
  if (!s.display.empty())
    with_context(names("display"), [&] { return spaces.display_from_xyz(s.display, s.view); });
  // Files that store integers are display-referred: an encoded space and 8 bits by default.
  // TIFF holds either: integers unless half or float is asked for.
  const std::string ext = lower_extension(output);
  const bool float_file = ext == ".exr" || ext == ".hdr" || ext == ".pfm";
  const bool tiff = ext == ".tif" || ext == ".tiff";
  const bool integer_file = !float_file && !(tiff && format_given && s.integer_bits == 0);
  if (integer_file && !format_given) s.integer_bits = 8;
  if (integer_file && s.integer_bits == 0)
    throw Error(names.output + " '" + clip(output) + "': " + names("format") +
                " uint8 or uint16 for this file type (half and float: .exr, .tif, .hdr, .pfm)");
  if (s.colorspace.empty() && s.display.empty())
    s.colorspace = default_colour_space(spaces, !integer_file).first;
  return s;
}

Settings checked_ingest_settings(Settings s, const OptionNames& names) {
  if (s.integer_bits != 0)
    throw Error(names("format") + ": a spectral OpenEXR stores half or float samples");
  resolve_colour_space(s, load_config(s, names), names);
  return s;
}

}  // namespace spectralize
