#include "settings/settings.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "core/colorimetry/renderer_frame.h"
#include "core/decimal_number.h"
#include "imagefile/output_formats.h"
#include "settings/map_kind.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"

namespace spectralize {

namespace {

constexpr unsigned kSpectrumCommands = kImage | kColor | kPlotColor | kIngest | kTable;
constexpr unsigned kFileCommands = kImage | kToRgb | kIngest;
constexpr unsigned kAllCommands =
    kImage | kToRgb | kColor | kPlotColor | kPlotPixel | kIngest | kTable;

const CommandName kCommandNames[] = {
    {kImage, "image"},    {kToRgb, "--to-rgb"},         {kColor, "--color"},
    {kPlotColor, "plot"}, {kPlotPixel, "--plot-pixel"}, {kIngest, "ingest"},
    {kTable, "table"}};

// A whole number in [lo, hi]; throws Error naming the value.
int whole(std::string_view text, int lo, int hi) {
  int v = 0;
  auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    throw Error(quote(text) + " is not a whole number");
  if (v < lo || v > hi)
    throw Error(quote(text) + " must be between " + std::to_string(lo) + " and " +
                std::to_string(hi));
  return v;
}

// One of `choices`; throws Error listing them.
std::string_view choice(std::string_view text, std::initializer_list<std::string_view> choices) {
  std::string valid;
  for (std::string_view c : choices) {
    if (c == text) return c;
    valid += (valid.empty() ? "" : ", ") + std::string(c);
  }
  throw Error(quote(text) + " (valid: " + valid + ")");
}

std::string shortest(double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

bool is_reflectance(const Settings& s) {
  return s.spectral.mode == Mode::reflectance;
}

// The compression as a writer takes it, NAME[:LEVEL]: a name some format takes, with a level
// in the range any format takes for it (a whole number; for dwaa/dwab a quality above 0). The
// output's own format checks it further before any work (imagefile/output_formats.h).
std::string parse_compression(std::string_view text) {
  const std::size_t colon = text.find(':');
  const std::string_view name = text.substr(0, colon);
  const auto& names = all_compression_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string valid;
    for (std::string_view c : names) valid += (valid.empty() ? "" : ", ") + std::string(c);
    throw Error(quote(text) + " (valid: " + valid + ", some with :LEVEL, e.g. zip:9, jpeg:90)");
  }
  if (colon == std::string_view::npos) return std::string(name);
  const std::string_view level = text.substr(colon + 1);
  int lo = 0, hi = 0;
  if (name == "dwaa" || name == "dwab") {
    double q = 0;
    try {
      q = decimal_number(level);
    } catch (const Error& e) {
      throw Error(quote(text) + ": the DWA quality " + e.what() + " (e.g. dwaa:45)");
    }
    if (!(q > 0))
      throw Error(quote(text) + ": the DWA quality must be a number above 0 (e.g. dwaa:45)");
  } else if (compression_level_range(name, lo, hi)) {
    try {
      whole(level, lo, hi);
    } catch (const Error& e) {
      throw Error(quote(text) + ": the " + std::string(name) + " level " + e.what());
    }
  } else {
    throw Error(quote(text) + ": " + std::string(name) + " takes no level");
  }
  return std::string(text);
}

// The models of the registry, for --help: "paper (the paper's average ...) or smooth (...)".
std::string model_help() {
  std::string text = "How the spectrum is chosen among the exact ones: ";
  const auto& models = spectrum_models();
  for (std::size_t i = 0; i < models.size(); ++i)
    text += (i == 0                   ? ""
             : i + 1 == models.size() ? " or "
                                      : ", ") +
            std::string(models[i].name) + " (" + std::string(models[i].summary) + ")";
  return text;
}

std::vector<SettingSpec> make_schema() {
  std::vector<SettingSpec> s;
  s.push_back({"colorspace", "--colorspace", "NAME", "colorspace",
               "Colour space of the input (--to-rgb: of the output): a name, alias or role of "
               "the OCIO config",
               kImage | kToRgb | kColor | kPlotColor | kIngest | kTable, true, false,
               [](Settings& v, std::string_view t) { v.colorspace = std::string(t); },
               [](const Settings& v) { return v.colorspace; },
               [](const Settings& v) { return !v.colorspace.empty(); },
               "from the file rules, the file, then the config's roles"});
  s.push_back({"mode", "--mode", "MODE", "mode",
               "emission (lights, HDR), reflectance (surfaces, 0 <= rho <= 1) or auto (a light "
               "or surface word of the name or its folders, else the image: values brighter than "
               "white are light; --color values are light; a table is for textures)",
               kSpectrumCommands, true, true,
               [](Settings& v, std::string_view t) {
                 const std::string_view c = choice(t, {"auto", "emission", "reflectance"});
                 v.mode = c == "auto"       ? ModeChoice::automatic
                          : c == "emission" ? ModeChoice::emission
                                            : ModeChoice::reflectance;
               },
               [](const Settings& v) { return std::string(to_string(v.mode)); }, nullptr});
  s.push_back({"wavelengths", "--wavelengths", "GRID", "wavelengths",
               "Sampling grid START:END:STEP in nm, inside 360..830, step >= 0.5",
               kSpectrumCommands, true, true,
               [](Settings& v, std::string_view t) { v.spectral.grid = WavelengthGrid::parse(t); },
               [](const Settings& v) { return v.spectral.grid.to_string(); }, nullptr});
  s.push_back({"observer", "--observer", "NAME", "observer",
               "CIE standard observer: cie1931 (2 degrees), cie1931_mitsuba (the same as "
               "Mitsuba 3 integrates it: at 5 nm, linear between) or cie1964 (10 degrees)",
               kAllCommands, true, true,
               [](Settings& v, std::string_view t) { v.spectral.observer = Observer::get(t).name; },
               [](const Settings& v) { return v.spectral.observer; }, nullptr});
  s.push_back(
      {"illuminant", "--illuminant", "NAME", "illuminant",
       "Reference illuminant of reflectances (--to-rgb, --plot-pixel: the light "
       "reflective files are seen under): D65, D50, A, C, E, D<nn>, <T>K, FL1..FL12, ...",
       kAllCommands, true, true,
       [](Settings& v, std::string_view t) { v.spectral.illuminant = Illuminant::get(t).name; },
       [](const Settings& v) { return v.spectral.illuminant; }, is_reflectance});
  s.push_back({"model", "--model", "NAME", "model", model_help(), kSpectrumCommands, true, true,
               [](Settings& v, std::string_view t) { v.spectral.model = RegisteredModel(t); },
               [](const Settings& v) { return std::string(v.spectral.model.name()); }, nullptr});
  s.push_back({"filter", "--filter", "K", "filter",
               "Paper model: drop the K partial solutions with the largest density: auto, a "
               "fraction (0.7), a percentage (70%), a count (1000) or none",
               kSpectrumCommands, true, true,
               [](Settings& v, std::string_view t) { v.spectral.filter = EdgeFilter::parse(t); },
               [](const Settings& v) { return v.spectral.filter.to_string(); },
               [](const Settings& v) { return v.spectral.model.uses("filter"); }});
  s.push_back({"curvature", "--curvature", "NM", "curvature",
               "Smooth model: the curvature length tau of its roughness x'^2 + tau^2 x''^2, in "
               "nm (0: slope only)",
               kSpectrumCommands, true, true,
               [](Settings& v, std::string_view t) {
                 const double tau = decimal_number(t);
                 if (!(tau >= 0) || !(tau <= 1000))
                   throw Error(quote(t) + " must be a length in nm from 0 to 1000");
                 v.spectral.curvature_nm = tau;
               },
               [](const Settings& v) { return shortest(v.spectral.curvature_nm); },
               [](const Settings& v) { return v.spectral.model.uses("curvature"); }});
  s.push_back(
      {"emission_basis", "--emission-basis", "NAME", "emissionBasis",
       "Emission: flat, or an illuminant E (D65, A, ...): spectrum = E x s with s >= 0, "
       "white balanced to E, so white light becomes E itself",
       kSpectrumCommands, true, true,
       [](Settings& v, std::string_view t) { v.spectral.emission_basis = parse_emission_basis(t); },
       [](const Settings& v) { return v.spectral.emission_basis; },
       [](const Settings& v) { return v.spectral.mode == Mode::emission; }});
  s.push_back(
      {"rgb_to_xyz", "--rgb-to-xyz", "MATRIX", "",
       "Table: a renderer's own RGB -> XYZ, which the spectra then reproduce exactly "
       "under the table's observer and illuminant (no D65 white balance): nine numbers "
       "m00,m01,...,m22 (row-major), or the primaries and the illuminant of the white, "
       "xr,yr,xg,yg,xb,yb,NAME (as pbrt-v4 builds its colour spaces)",
       kTable, true, false,
       [](Settings& v, std::string_view t) { v.rgb_to_xyz = RendererMatrix::parse(t).to_string(); },
       [](const Settings& v) { return v.rgb_to_xyz; },
       [](const Settings& v) { return !v.rgb_to_xyz.empty(); },
       "the colour space's, white balanced (docs/DESIGN.md section 3)"});
  s.push_back({"format", "--format", "FORMAT", "",
               "Samples of the written file: half (max 65504; larger samples are clamped and "
               "counted) or float; --to-rgb into PNG, JPEG, TIFF, ...: uint8 or uint16",
               kFileCommands, true, false,
               [](Settings& v, std::string_view t) {
                 const std::string_view c = choice(t, {"half", "float", "uint8", "uint16"});
                 v.half = c == "half";
                 v.integer_bits = c == "uint8" ? 8 : c == "uint16" ? 16 : 0;
               },
               [](const Settings& v) {
                 return std::string(v.integer_bits == 8    ? "uint8"
                                    : v.integer_bits == 16 ? "uint16"
                                    : v.half               ? "half"
                                                           : "float");
               },
               nullptr, "", "-d"});
  s.push_back({"print_format", "--format", "FORMAT", "",
               "How --color prints spectra: csv (wavelength_nm,value rows) or json (every field "
               "of the result)",
               kColor, false, false,
               [](Settings& v, std::string_view t) {
                 const std::string_view c = choice(t, {"csv", "json"});
                 v.json = c == "json";
               },
               [](const Settings& v) { return std::string(v.json ? "json" : "csv"); }, nullptr});
  s.push_back({"compression", "--compression", "NAME", "",
               "Compression, NAME[:LEVEL] as the output's format takes it: " + compression_help(),
               kFileCommands, true, false,
               [](Settings& v, std::string_view t) { v.compression = parse_compression(t); },
               [](const Settings& v) { return v.compression; }, nullptr,
               "zip; --to-rgb: the format's own (TIFF zip, PNG zip:6, JPEG jpeg:98)"});
  s.push_back({"tile", "--tile", "N", "",
               "Write N x N tiles (also --tile W H, or WxH), 16..4096, instead of scanlines (0)",
               kFileCommands, true, false,
               [](Settings& v, std::string_view t) {
                 const std::size_t x = t.find_first_of("x,");
                 const int w = whole(t.substr(0, x), 0, 4096);
                 const int h = x == std::string_view::npos ? w : whole(t.substr(x + 1), 0, 4096);
                 if ((w == 0) != (h == 0) || (w != 0 && (w < 16 || h < 16)))
                   throw Error(quote(t) + " must be 0 (scanlines) or sizes between 16 and 4096");
                 v.tile_width = w;
                 v.tile_height = h;
               },
               [](const Settings& v) {
                 return v.tile_width == v.tile_height
                            ? std::to_string(v.tile_width)
                            : std::to_string(v.tile_width) + "x" + std::to_string(v.tile_height);
               },
               nullptr});
  s.push_back({"preview_colorspace", "--preview-colorspace", "NAME", "previewColorSpace",
               "Colour space of the spectral file's R, G, B previews (tagged in the file)",
               kImage | kIngest, true, false,
               [](Settings& v, std::string_view t) { v.preview_colorspace = std::string(t); },
               [](const Settings& v) { return v.preview_colorspace; },
               [](const Settings& v) { return !v.preview_colorspace.empty(); },
               "the config's scene_linear role"});
  s.push_back({"reflected", "--reflected", "HOW", "",
               "Reflective files: balanced (relative to the reflected white: rho == 1 is RGB 1,1,1 "
               "under any light) or as-lit (the reflected light's colour: a white surface under A "
               "is warm)",
               kToRgb | kPlotPixel, true, false,
               [](Settings& v, std::string_view t) {
                 v.as_lit = choice(t, {"balanced", "as-lit"}) == "as-lit";
               },
               [](const Settings& v) { return std::string(v.as_lit ? "as-lit" : "balanced"); },
               nullptr});
  s.push_back({"display", "--display", "NAME", "",
               "An OCIO display for the output (with --view) instead of --colorspace", kToRgb, true,
               false, [](Settings& v, std::string_view t) { v.display = std::string(t); },
               [](const Settings& v) { return v.display; },
               [](const Settings& v) { return !v.display.empty(); }, "none"});
  s.push_back({"view", "--view", "NAME", "", "The OCIO view of --display", kToRgb, true, false,
               [](Settings& v, std::string_view t) { v.view = std::string(t); },
               [](const Settings& v) { return v.view; },
               [](const Settings& v) { return !v.view.empty(); }, "the display's default"});
  s.push_back({"plot_scale", "--plot-scale", "SCALE", "",
               "Value axis of plots: linear, log (a sun and a sky on one plot) or normalized "
               "(each curve divided by its maximum)",
               kPlotColor | kPlotPixel, false, false,
               [](Settings& v, std::string_view t) {
                 const std::string_view c = choice(t, {"linear", "log", "normalized"});
                 v.plot_scale = c == "log"      ? PlotScale::log
                                : c == "linear" ? PlotScale::linear
                                                : PlotScale::normalized;
               },
               [](const Settings& v) { return std::string(to_string(v.plot_scale)); }, nullptr});
  // Batch ingest (ingest/ingest.h).
  s.push_back({"name_pattern", "--name-pattern", "PATTERN", "",
               "Output path under the destination: {dir} (the input's folder relative to its "
               "source), {stem}, {ext}; must end in .exr",
               kIngest, false, false,
               [](Settings& v, std::string_view t) {
                 const std::string p(t);
                 if (p.size() < 5 || p.substr(p.size() - 4) != ".exr" ||
                     p.find("{stem}") == std::string::npos)
                   throw Error(quote(t) + " must contain {stem} and end in .exr");
                 v.ingest.name_pattern = p;
               },
               [](const Settings& v) { return v.ingest.name_pattern; }, nullptr});
  s.back().shapes_file = false;  // where the outputs go
  for (const bool colour : {false, true}) {
    s.push_back(
        {colour ? "colour_names" : "data_names", colour ? "--colour-names" : "--data-names",
         "WORDS", "",
         colour ? "Edit the name table's colour words (WORD or WORD:emission, a surface's "
                  "colour or a light's): a list replaces them, +WORD,-WORD edits them"
                : "Edit the name table's words of non-colour data (never spectralized by "
                  "ingest): a list replaces them, +WORD,-WORD edits them",
         kImage | kIngest, false, false,
         [colour](Settings& v, std::string_view t) {
           (colour ? v.colour_names : v.data_names) = check_name_edit(t, colour);
         },
         [colour](const Settings& v) { return colour ? v.colour_names : v.data_names; },
         [colour](const Settings& v) { return !(colour ? v.colour_names : v.data_names).empty(); },
         "the name table of the guide's pipeline chapter"});
    // Decisions: recorded by what they resolve to for each file (its mode, or data skipped),
    // so a changed table redoes only the files it decides otherwise.
    s.back().shapes_file = false;
  }
  s.push_back({"data", "--data", "ACTION", "",
               "Non-colour files (data colour spaces, data names): skip or copy them unchanged",
               kIngest, false, false,
               [](Settings& v, std::string_view t) {
                 v.ingest.copy_data = choice(t, {"skip", "copy"}) == "copy";
               },
               [](const Settings& v) { return std::string(v.ingest.copy_data ? "copy" : "skip"); },
               nullptr});
  s.back().shapes_file = false;  // what happens to data files, not to spectral ones
  s.push_back({"jobs", "--jobs", "N", "",
               "Files converted at once (0: one per core; each gets its share of --threads)",
               kIngest, false, false,
               [](Settings& v, std::string_view t) { v.ingest.jobs = whole(t, 0, 256); },
               [](const Settings& v) { return std::to_string(v.ingest.jobs); }, nullptr});
  s.back().shapes_file = false;  // how the batch runs
  s.push_back({"method", "--method", "METHOD", "method",
               "table (the exact table's blend of node spectra, the spectra a renderer's table "
               "file gives) or exact (every distinct colour solved directly: double precision "
               "and the model's details; slow)",
               kImage | kIngest | kColor | kPlotColor, true, false,
               [](Settings& v, std::string_view t) {
                 v.method = choice(t, {"table", "exact"}) == "table" ? SpectralTable::Method::table
                                                                     : SpectralTable::Method::exact;
               },
               [](const Settings& v) {
                 return std::string(v.method == SpectralTable::Method::table ? "table" : "exact");
               },
               nullptr});
  s.push_back({"cache", "--cache", "DIR", "",
               "Keep the node table in DIR across runs (a file per combination of the settings "
               "the spectra depend on)",
               kImage | kIngest, true, false,
               [](Settings& v, std::string_view t) { v.cache_dir = std::string(t); },
               [](const Settings& v) { return v.cache_dir; },
               [](const Settings& v) { return !v.cache_dir.empty(); }, "none"});
  s.back().shapes_file = false;  // how the job runs (the spectra do not depend on it)
  s.push_back({"threads", "--threads", "N", "",
               "Cores to use: conversion and compression workers (0: all; 1: one core); the output "
               "does not depend on it",
               kFileCommands | kTable, true, false,
               [](Settings& v, std::string_view t) { v.threads = whole(t, 0, 1024); },
               [](const Settings& v) { return std::to_string(v.threads); }, nullptr});
  s.back().shapes_file = false;  // how the job runs (the output does not depend on it)
  s.push_back({"config", "--config", "FILE", "",
               "OCIO config (default: $OCIO, else the config shipped with spectralize)",
               kAllCommands, true, false,
               [](Settings& v, std::string_view t) { v.config = std::string(t); },
               [](const Settings& v) { return v.config; },
               [](const Settings& v) { return !v.config.empty(); },
               "$OCIO, else the shipped config", "--colorconfig"});
  // The config enters ingest's key by its content (ColourSpaces::content_identity).
  s.back().shapes_file = false;
  return s;
}

}  // namespace

std::string_view to_string(PlotScale scale) {
  return scale == PlotScale::log ? "log" : scale == PlotScale::normalized ? "normalized" : "linear";
}

std::string_view to_string(ModeChoice mode) {
  switch (mode) {
    case ModeChoice::automatic:
      return "auto";
    case ModeChoice::emission:
      return "emission";
    case ModeChoice::reflectance:
      return "reflectance";
  }
  return "auto";
}

std::span<const CommandName> command_names() {
  return kCommandNames;
}

const std::vector<SettingSpec>& settings_schema() {
  static const std::vector<SettingSpec> schema = [] {
    std::vector<SettingSpec> s = make_schema();
    // Settings::given holds one bit per setting.
    if (s.size() > 64) throw std::logic_error("more than 64 settings: widen Settings::given");
    return s;
  }();
  return schema;
}

namespace {

// The place of `spec` in the schema (its bit in Settings::given).
std::size_t schema_index(const SettingSpec& spec) {
  return static_cast<std::size_t>(&spec - settings_schema().data());
}

}  // namespace

const SettingSpec* find_setting(std::string_view key) {
  for (const SettingSpec& s : settings_schema())
    if (s.key == key) return &s;
  return nullptr;
}

const SettingSpec* find_setting_for_flag(std::string_view flag, Command command) {
  for (const SettingSpec& s : settings_schema())
    if ((s.flag == flag || (!s.alias.empty() && s.alias == flag)) && s.applies(command)) return &s;
  return nullptr;
}

unsigned flag_commands(std::string_view flag) {
  unsigned commands = 0;
  for (const SettingSpec& s : settings_schema())
    if (s.flag == flag || (!s.alias.empty() && s.alias == flag)) commands |= s.commands;
  return commands;
}

void apply_setting(Settings& settings, const SettingSpec& spec, std::string_view text,
                   std::string_view where) {
  if (text.empty())
    throw Error(std::string(where) + ": an empty value (give a value or leave the option out)");
  with_context(where, [&] { spec.parse(settings, text); });
  settings.given |= std::uint64_t{1} << schema_index(spec);
}

bool was_given(const Settings& settings, const SettingSpec& spec) {
  return (settings.given >> schema_index(spec)) & 1;
}

void set_aside(Settings& settings, const SettingSpec& spec) {
  settings.given &= ~(std::uint64_t{1} << schema_index(spec));
}

const SettingSpec* ineffective_setting(const Settings& settings, std::optional<Mode> decided) {
  for (const SettingSpec& spec : settings_schema()) {
    if (!was_given(settings, spec) || !spec.relevant) continue;
    bool shapes = false;
    for (Mode mode : {Mode::emission, Mode::reflectance}) {
      if (decided && mode != *decided) continue;
      Settings s = settings;
      s.spectral.mode = mode;
      shapes = shapes || spec.matters(s);
    }
    if (!shapes) return &spec;
  }
  return nullptr;
}

std::string setting_value(const SettingSpec& spec, const Settings& settings) {
  // What was done is the resolved mode, whatever was asked ("auto").
  if (spec.key == "mode") return std::string(to_string(settings.spectral.mode));
  return spec.format(settings);
}

std::vector<std::pair<std::string, std::string>> describe_settings(const Settings& settings,
                                                                   Command command,
                                                                   bool spectral_only) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const SettingSpec& s : settings_schema()) {
    if (!s.applies(command) || !s.matters(settings) || (spectral_only && !s.spectral)) continue;
    out.emplace_back(std::string(s.key), setting_value(s, settings));
  }
  return out;
}

std::vector<std::pair<const SettingSpec*, std::string>> file_settings(const Settings& resolved) {
  std::vector<std::pair<const SettingSpec*, std::string>> out;
  for (const SettingSpec& s : settings_schema())
    if (s.shapes_file && s.applies(kImage) && s.matters(resolved))
      out.emplace_back(&s, setting_value(s, resolved));
  return out;
}

std::string table_cache_key(const Settings& settings, const std::string& table_layout) {
  std::string key = "spectralize " SPECTRALIZE_VERSION " node table";
  for (const SettingSpec& s : settings_schema()) {
    if (!s.spectral || !s.matters(settings)) continue;
    key += "; " + std::string(s.key) + " " + setting_value(s, settings);
  }
  return key + "; " + table_layout;
}

}  // namespace spectralize
