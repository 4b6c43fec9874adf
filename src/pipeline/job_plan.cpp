#include "pipeline/job_plan.h"

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
  r.channels = spectral_output_channels(s, false);
  return r;
}

// The job's one load of the config.
std::shared_ptr<const ColourSpaces> load_config(const Settings& s, const OptionNames& names) {
  if (s.config.empty()) return std::make_shared<const ColourSpaces>(ColourSpaces::load());
  try {
    return std::make_shared<const ColourSpaces>(
        with_context(names("config"), [&] { return ColourSpaces::load(s.config); }));
  } catch (const ConfigError& e) {
    throw ConfigError(names("config") + ": " + e.what());  // still the config's fault (exit 1)
  }
}

JobPlan plan_of(Settings s, std::shared_ptr<const ColourSpaces> spaces, const OptionNames& names,
                bool to_rgb) {
  JobPlan plan;
  plan.settings = std::move(s);
  plan.names = names;
  plan.spaces = std::move(spaces);
  plan.to_rgb = to_rgb;
  return plan;
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

JobPlan plan_to_spectral(Settings s, const std::string& output, const OptionNames& names) {
  if (output.empty()) {  // a batch's outputs
    if (s.integer_bits != 0)
      throw Error(names("format") + ": a spectral OpenEXR stores half or float samples");
    check_format(*output_format_named("openexr"), spectral_request(s),
                 "the outputs (OpenEXR): ", names.prefix);
  } else {
    if (lower_extension(output) != ".exr")
      throw Error(names.output + " '" + clip(output) +
                  "': the output is a spectral OpenEXR file (.exr)");
    if (s.integer_bits != 0)
      throw Error(names("format") + " uint" + std::to_string(s.integer_bits) +
                  ": a spectral OpenEXR stores half or float samples");
    check_output(output, spectral_request(s), names.prefix);
  }
  auto spaces = load_config(s, names);
  resolve_colour_space(s, *spaces, names);
  return plan_of(std::move(s), std::move(spaces), names, false);
}

JobPlan plan_to_rgb(Settings s, const std::string& output, bool format_given,
                    bool compression_given, const OptionNames& names) {
  // No output: a reader presents the RGB (the plugin), in float.
  const OutputFormat* format = output.empty() ? nullptr : output_format_for(output);
  if (!output.empty() && !format)
    throw Error(names.output + " '" + clip(output) +
                "': an image file OpenImageIO writes (.exr, .tif, .png, .jpg, .hdr, ...)");
  if (format) {
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
  }
  auto loaded = load_config(s, names);
  const ColourSpaces& spaces = *loaded;
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
  return plan_of(std::move(s), std::move(loaded), names, true);
}

Mode mode_of_subject(ModeChoice asked, ColourSubject subject) {
  if (asked == ModeChoice::reflectance) return Mode::reflectance;
  if (asked == ModeChoice::emission) return Mode::emission;
  // No data type to decide by: float values are light, as float images are; a table is looked
  // up by textures, which are surfaces.
  return subject == ColourSubject::table ? Mode::reflectance : Mode::emission;
}

JobPlan plan_colours(Settings s, ColourSubject subject, const OptionNames& names) {
  auto spaces = load_config(s, names);
  resolve_colour_space(s, *spaces, names);
  const bool display = subject == ColourSubject::spectra && !s.display.empty();
  if (subject == ColourSubject::spectra) {
    if (!s.display.empty() && !s.colorspace.empty())
      throw Error("give " + names("colorspace") + " or " + names("display") + ", not both");
    if (!s.view.empty() && s.display.empty())
      throw Error(names("view") + " needs " + names("display"));
  }
  if (s.colorspace.empty() && !display) s.colorspace = default_colour_space(*spaces, true).first;
  s.spectral.mode = mode_of_subject(s.mode, subject);
  if (subject == ColourSubject::table)
    s.mode = s.spectral.mode == Mode::emission ? ModeChoice::emission : ModeChoice::reflectance;
  // As for an image (classify/input_interpretation.h): a data space's values are not a colour.
  std::vector<std::string> warnings;
  if (subject == ColourSubject::colours && spaces->is_data(s.colorspace))
    warnings.push_back(data_space_warning(s.colorspace));
  JobPlan plan = plan_of(std::move(s), std::move(spaces), names, subject == ColourSubject::spectra);
  plan.warnings = std::move(warnings);
  return plan;
}

int spectral_output_channels(const Settings& settings, bool alpha) {
  return static_cast<int>(settings.spectral.grid.size()) + 3 + (alpha ? 1 : 0);
}

JobPlan planned_input(const JobPlan& plan, const std::string& input, const OIIO::ImageSpec& spec,
                      const InputInterpretation* colour_decided) {
  JobPlan p = plan;
  p.input = input;
  const ColourSpaces& spaces = *p.spaces;
  if (p.to_rgb) {
    p.spectral = analyse_spectral_layout(spec, input);
    p.settings.spectral.mode = p.spectral.emissive ? Mode::emission : Mode::reflectance;
    p.output_channels = p.spectral.alpha >= 0 ? 4 : 3;
    return p;
  }
  if (colour_decided) {
    p.interpretation = *colour_decided;
    decide_light_or_surface(p.interpretation, input, spec, plan.settings, spaces);
  } else {
    p.interpretation = interpret_input(input, spec, plan.settings, spaces);
  }
  // Mode, colour space and preview space as decided for this file: what the header records.
  p.settings = resolved_settings(plan.settings, p.interpretation, spaces);
  p.output_channels = spectral_output_channels(p.settings, p.interpretation.channels.alpha >= 0);
  return p;
}

}  // namespace spectralize
