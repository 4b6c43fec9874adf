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

}  // namespace

// The one place a colour-space name given by the user is resolved: into the plan's records,
// the settings keeping the canonical names. Every space named by an option is checked before
// any work, the same way.
void resolve_colour_spaces(JobPlan& plan) {
  Settings& s = plan.settings;
  const ColourSpaces& spaces = *plan.spaces;
  // Named by who gave it: the option, or a list line's origin (a USD stage's declaration).
  plan.colorspace =
      with_context(s.colorspace_given_by.empty() ? plan.names("colorspace") : s.colorspace_given_by,
                   [&] { return spaces.named(s.colorspace); });
  plan.preview_colorspace = with_context(plan.names("preview_colorspace"),
                                         [&] { return spaces.named(s.preview_colorspace); });
  if (plan.colorspace) s.colorspace = plan.colorspace.name();
  if (plan.preview_colorspace) s.preview_colorspace = plan.preview_colorspace.name();
}

namespace {

// A plan of the checked settings with the config loaded and the named spaces resolved.
JobPlan plan_of(Settings s, const OptionNames& names, bool to_rgb) {
  JobPlan plan;
  plan.spaces = load_config(s, names);
  plan.settings = std::move(s);
  plan.names = names;
  plan.to_rgb = to_rgb;
  resolve_colour_spaces(plan);
  return plan;
}

// A setting the user gave that cannot shape what the job makes (`what`) is a mistake to say,
// not to ignore: every front end (the commands, Python, recipes) refuses it the same way,
// before any work. `decided`: the job's mode, or none when each input decides its own.
void refuse_ineffective(const JobPlan& plan, std::optional<Mode> decided, const std::string& what) {
  if (const SettingSpec* spec = ineffective_setting(plan.settings, decided))
    throw Error(plan.names(std::string(spec->key)) + " does not shape " + what + "; leave it out");
}

std::string of_model(const Settings& s) {
  return " of the " + std::string(s.spectral.model.name()) + " model";
}

// "an emission", "a reflectance".
std::string a_mode(Mode mode) {
  return mode == Mode::emission ? "an emission" : "a reflectance";
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
  JobPlan plan = plan_of(std::move(s), names, false);
  const Settings& p = plan.settings;
  if (p.mode == ModeChoice::automatic)
    refuse_ineffective(plan, std::nullopt,
                       "the spectra" + of_model(p) + ", a light's or a surface's");
  else
    refuse_ineffective(plan, p.mode == ModeChoice::emission ? Mode::emission : Mode::reflectance,
                       std::string(to_string(p.mode)) + " spectra" + of_model(p));
  return plan;
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
  JobPlan plan = plan_of(std::move(s), names, true);
  Settings& p = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  if (!p.display.empty() && !p.colorspace.empty())
    throw Error("give " + names("colorspace") + " or " + names("display") + ", not both");
  if (!p.view.empty() && p.display.empty())
    throw Error(names("view") + " needs " + names("display"));
  if (!p.display.empty())
    with_context(names("display"), [&] { return spaces.display_from_xyz(p.display, p.view); });
  // Integer samples are display-referred: an encoded space by default; float ones linear.
  if (p.colorspace.empty() && p.display.empty()) {
    p.colorspace = default_colour_space(spaces, p.integer_bits == 0).first;
    plan.colorspace = spaces.named(p.colorspace);
  }
  // The mode is the spectral file's own.
  refuse_ineffective(plan, std::nullopt, "RGB from spectra");
  return plan;
}

Mode mode_of_subject(ModeChoice asked, ColourSubject subject) {
  if (asked == ModeChoice::reflectance) return Mode::reflectance;
  if (asked == ModeChoice::emission) return Mode::emission;
  // No data type to decide by: float values are light, as float images are; a table is looked
  // up by textures, which are surfaces.
  return subject == ColourSubject::table ? Mode::reflectance : Mode::emission;
}

JobPlan plan_colours(Settings settings, ColourSubject subject, const OptionNames& names) {
  JobPlan plan = plan_of(std::move(settings), names, subject == ColourSubject::spectra);
  Settings& s = plan.settings;
  const ColourSpaces& spaces = plan.colour_spaces();
  const bool display = subject == ColourSubject::spectra && !s.display.empty();
  if (subject == ColourSubject::spectra) {
    if (!s.display.empty() && !s.colorspace.empty())
      throw Error("give " + names("colorspace") + " or " + names("display") + ", not both");
    if (!s.view.empty() && s.display.empty())
      throw Error(names("view") + " needs " + names("display"));
  }
  if (s.colorspace.empty() && !display) {
    s.colorspace = default_colour_space(spaces, true).first;
    plan.colorspace = spaces.named(s.colorspace);
  }
  s.spectral.mode = mode_of_subject(s.mode, subject);
  if (subject == ColourSubject::table)
    s.mode = s.spectral.mode == Mode::emission ? ModeChoice::emission : ModeChoice::reflectance;
  // As for an image (classify/input_interpretation.h): a data space's values are not a colour.
  if (subject == ColourSubject::colours && plan.colorspace.facts->data)
    plan.warnings.push_back(data_space_warning(s.colorspace));
  refuse_ineffective(plan, s.spectral.mode,
                     subject == ColourSubject::table
                         ? a_mode(s.spectral.mode) + " table" + of_model(s)
                         : std::string(to_string(s.spectral.mode)) + " spectra" + of_model(s));
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
