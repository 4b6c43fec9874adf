// Plots: `spectralize --color R,G,B ... -o PLOT.png|.svg` and `spectralize --plot-pixel X,Y
// IN.exr -o PLOT.png|.svg`. The drawing is plot/spectrum_plot; this file gathers the spectra, the
// title and the swatches (the colour before and after the round trip, through OCIO).

#include <OpenImageIO/imageio.h>
#include <fmt/core.h>
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "imagefile/image_reader.h"
#include "imagefile/safe_output.h"
#include "pipeline/job_plan.h"
#include "pipeline/rgb_from_spectral.h"
#include "plot/spectrum_plot.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"
#include "text/strings.h"
#include "tool/colour_values.h"
#include "tool/options.h"

namespace fs = std::filesystem;

namespace spectralize::tool {

namespace {

// Display colours of the swatches: CIE XYZ (D65) -> the config's display-referred space
// (plot/spectrum_plot.h's PlotSpaces: its roles, not fixed names) by OCIO. Colours brighter than
// display white (HDR lights) are scaled down first, by the factor that brings the colour's
// largest component in the config's scene_linear space to 1, the same for both swatches of a
// curve so they stay comparable.
class SwatchColours {
 public:
  explicit SwatchColours(const PlotSpaces& cs)
      : display_(cs.spaces->from_xyz(cs.encoded)), linear_(cs.spaces->from_xyz(cs.linear)) {}

  /// The factor (<= 1) that fits `xyz` into the display's range. Cost: O(1) + OCIO.
  double exposure(const Xyz& xyz) const {
    float rgb[3] = {static_cast<float>(xyz.X), static_cast<float>(xyz.Y),
                    static_cast<float>(xyz.Z)};
    linear_.apply(rgb, 1);
    const double m = std::max({rgb[0], rgb[1], rgb[2]});
    return std::isfinite(m) && m > 1 ? 1 / m : 1;
  }
  /// `xyz` times `k` in the display-referred space, clipped to [0, 1]. Cost: O(1) + OCIO.
  PlotColour operator()(const Xyz& xyz, double k) const {
    float rgb[3] = {static_cast<float>(k * xyz.X), static_cast<float>(k * xyz.Y),
                    static_cast<float>(k * xyz.Z)};
    display_.apply(rgb, 1);
    auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; };
    return {unit(rgb[0]), unit(rgb[1]), unit(rgb[2])};
  }

 private:
  ColourTransform display_, linear_;
};

// -o must name a plot file (.svg or an image format OIIO writes).
void check_plot_output(const Options& opt, const char* command) {
  if (opt.output.empty())
    throw UsageError{fmt::format("{} needs -o PLOT.png or -o PLOT.svg", command)};
  if (!is_plot_path(opt.output))
    throw UsageError{fmt::format(
        "-o '{}': a plot is written as .svg or as an image OpenImageIO writes (.png, .jpg, .tif, "
        ".exr, ...)",
        clip(opt.output))};
  try {
    check_plot_file(opt.output);
  } catch (const Error& e) {
    throw UsageError{e.what()};
  }
}

// The settings line of a --color plot: colour space, then the settings that mattered (from the
// schema), e.g. "sRGB - Texture | reflectance | illuminant D65 | model paper | filter auto".
std::string settings_line(const std::string& space, const Options& opt, const Spectralizer& sp) {
  Settings s = opt.settings;
  s.spectral = sp.settings();
  std::string line = space;
  for (const auto& [key, value] : describe_settings(s, kPlotColor)) {
    if (key == "colorspace" || key == "config") continue;
    line += " | " + (key == "mode" ? value : key + " " + value);
  }
  return line;
}

// Parses "X,Y": two whole numbers >= 0.
std::pair<int, int> parse_pixel(const std::string& text) {
  const std::size_t comma = text.find(',');
  auto whole = [&](std::string_view part, int& v) {
    auto r = std::from_chars(part.data(), part.data() + part.size(), v);
    return !part.empty() && r.ec == std::errc() && r.ptr == part.data() + part.size() && v >= 0;
  };
  int x = 0, y = 0;
  if (comma == std::string::npos || !whole(std::string_view(text).substr(0, comma), x) ||
      !whole(std::string_view(text).substr(comma + 1), y))
    throw UsageError{fmt::format(
        "--plot-pixel '{}': expected X,Y, two whole numbers >= 0 (0,0 is the top-left pixel)",
        text)};
  return {x, y};
}

// --plot-scale: decades, or each curve divided by its own maximum (so a sun pixel and a sky
// pixel can share a plot).
void apply_scale(const Options& opt, SpectrumPlot& plot) {
  switch (opt.settings.plot_scale) {
    case PlotScale::linear:
      return;
    case PlotScale::log:
      plot.log_scale = true;
      plot.y_label += " (log)";
      return;
    case PlotScale::normalized:
      for (PlotCurve& c : plot.curves) {
        double peak = 0;
        for (double v : c.values)
          if (std::isfinite(v)) peak = std::max(peak, v);
        if (peak > 0)
          for (double& v : c.values) v /= peak;
      }
      plot.y_label += " / its maximum";
      plot.y_top_at_least = 1;
      return;
  }
}

// The curves of a plot as CSV: wavelength_nm, then one column per curve (named by its label).
std::string plot_csv(const SpectrumPlot& plot) {
  std::string text = "wavelength_nm";
  for (const PlotCurve& c : plot.curves) text += ",\"" + c.label + "\"";
  text += "\n";
  const std::size_t n = plot.curves.empty() ? 0 : plot.curves[0].wavelengths.size();
  for (std::size_t k = 0; k < n; ++k) {
    text += fmt::format("{}", plot.curves[0].wavelengths[k]);
    for (const PlotCurve& c : plot.curves) text += fmt::format(",{}", c.values[k]);
    text += "\n";
  }
  return text;
}

// The plot writer's warnings (a format that cannot say the plot's colour space), on stderr.
void warn(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) fmt::print(stderr, "spectralize WARNING: {}\n", w);
}

void report(const Options& opt, const SpectrumPlot& plot) {
  if (opt.verbosity > 0)
    fmt::print(stderr, "spectralize: '{}': plot of {} spectr{}, {} samples, {}x{}\n", opt.output,
               plot.curves.size(), plot.curves.size() == 1 ? "um" : "a",
               plot.curves.empty() ? 0 : plot.curves[0].values.size(), kPlotWidth, kPlotHeight);
}

}  // namespace

int run_plot_color(const Options& opt) {
  // Validate every flag before any work (exit 2 on a mistake).
  check_plot_output(opt, "--color");
  if (opt.colors.size() > kMaxPlotCurves)
    throw UsageError{fmt::format("--color: a plot shows at most {} colours, got {}", kMaxPlotCurves,
                                 opt.colors.size())};
  const ColourInputs in = colour_inputs(opt);
  const auto& [settings, colours, spaces, to_xyz, frame] = in;
  const PlotSpaces cs = plot_spaces(*spaces);
  const SwatchColours swatch(cs);

  Spectralizer spectralizer(settings);
  std::unique_ptr<SpectralTable> table;
  if (opt.settings.method == SpectralTable::Method::table)
    table = std::make_unique<SpectralTable>(spectralizer, SpectralTable::Method::table, frame);
  // The spectrum's XYZ is in the target's terms; a reflectance's target is white balanced to
  // the reference illuminant, so undo that to compare with the input (emission: factor 1).
  const Xyz unbalance = spectralizer.unbalance();

  SpectrumPlot plot;
  plot.y_label =
      settings.mode == Mode::emission ? "relative spectral radiance" : "reflectance (rho)";
  plot.y_top_at_least = settings.mode == Mode::reflectance ? 1 : 0;
  plot.swatch_labels = {"input", "round trip"};
  int status = kExitOk;
  bool scaled = false;
  std::vector<std::string> results;  // one-colour details for the title
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const Rgb& c = colours[i];
    const SpectrumResult r = spectralize_colour(spectralizer, table.get(), to_xyz, c, status);
    PlotCurve curve;
    curve.label = c.text + (r.status == Outcome::exact || r.status == Outcome::black
                                ? ""
                                : " (" + std::string(to_string(r.status)) + ")");
    for (std::size_t k = 0; k < settings.grid.size(); ++k)
      curve.wavelengths.push_back(settings.grid[k]);
    curve.values = r.values;
    curve.colour = plot_palette(i);
    const double k = swatch.exposure(r.input);
    scaled = scaled || k < 1;
    curve.swatches = {swatch(r.input, k), swatch(hadamard(r.xyz, unbalance), k)};
    plot.curves.push_back(std::move(curve));
    // The model's own details (the paper model: L and K, and whether the bound acted).
    std::string details;
    for (const ModelDetail& d : r.details)
      if (!d.boolean)
        details += fmt::format(" | {} {}", d.name, d.value);
      else if (d.value != 0)
        details += " | " + d.name;
    results.push_back(fmt::format("{} | relative XYZ error {:.2g}{}", to_string(r.status),
                                  r.relative_error, details));
  }
  plot.title = {colours.size() == 1 ? fmt::format("Spectrum of RGB ({})", colours[0].text)
                                    : fmt::format("Spectra of {} colours", colours.size()),
                settings_line(to_xyz.source(), opt, spectralizer)};
  if (colours.size() == 1) plot.title.push_back(results[0]);
  plot.notes.push_back("swatches: " + cs.encoded + " via OCIO");
  if (scaled) plot.notes.push_back("bright lights scaled to fit");
  apply_scale(opt, plot);
  warn(write_plot(plot, opt.output, cs));
  report(opt, plot);
  return status;
}

int run_plot_pixel(const Options& opt) {
  // Validate the command line before reading anything (exit 2 on a mistake).
  if (!opt.colors.empty() || !opt.to_rgb.empty())
    throw UsageError{"--plot-pixel plots a pixel of a spectral EXR: give no --color or --to-rgb"};
  if (opt.inputs.size() != 1)
    throw UsageError{
        opt.inputs.empty()
            ? "--plot-pixel needs the spectral EXR: spectralize --plot-pixel X,Y "
              "IN.exr -o PLOT.png"
            : fmt::format("--plot-pixel: one input file at a time, got {}", opt.inputs.size())};
  // -o PIXELS.csv writes the samples themselves instead of a plot.
  const std::string ext = fs::path(opt.output).extension().string();
  const bool csv = ext == ".csv" || ext == ".CSV";
  if (!csv) check_plot_output(opt, "--plot-pixel");
  if (opt.plot_pixels.size() > kMaxPlotCurves)
    throw UsageError{fmt::format("--plot-pixel: a plot shows at most {} pixels, got {}",
                                 kMaxPlotCurves, opt.plot_pixels.size())};
  std::vector<std::pair<int, int>> pixels;
  for (const auto& text : opt.plot_pixels) pixels.push_back(parse_pixel(text));
  const std::string& observer = opt.settings.spectral.observer;
  const std::string& illuminant = opt.settings.spectral.illuminant;
  // Spectra to RGB without an output format (the plot's own): the config, loaded once.
  const JobPlan plan = usage_checked("", [&] {
    return plan_colours(opt.settings, ColourSubject::spectra, OptionNames{"--", "-o"});
  });
  const ColourSpaces& spaces = plan.colour_spaces();
  const PlotSpaces cs = plot_spaces(spaces);
  const SwatchColours swatch(cs);

  // Open the file (scanline, tiled or MIP-mapped: level 0); never write over it.
  const std::string& file = opt.inputs[0];
  ImageReader in(file, 4);
  const OIIO::ImageSpec& spec = in.spec();
  const SpectralLayoutInfo layout = analyse_spectral_layout(spec, file);
  Settings rgb_settings = opt.settings;
  rgb_settings.colorspace = cs.linear;
  const std::string& linear = rgb_settings.colorspace;
  const RgbFromSpectral to_rgb(layout, rgb_settings, spaces);
  const ColourTransform rgb_to_xyz = spaces.to_xyz(linear);
  const int r_ch = spec.channelindex("R"), g_ch = spec.channelindex("G"),
            b_ch = spec.channelindex("B");
  const bool has_rgb = r_ch >= 0 && g_ch >= 0 && b_ch >= 0;

  SpectrumPlot plot;
  const std::string units = spec.get_string_attribute("emissiveUnits");
  plot.y_label =
      layout.emissive ? (units.empty() ? "S0" : "S0 (" + units + ")") : "T (reflectance)";
  plot.y_top_at_least = layout.emissive ? 0 : 1;
  plot.swatch_labels = {"spectrum -> RGB"};
  if (has_rgb) plot.swatch_labels.insert(plot.swatch_labels.begin(), "file's RGB");
  bool scaled = false;
  std::vector<float> row(static_cast<std::size_t>(spec.width) * spec.nchannels);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const auto [x, y] = pixels[i];
    if (x >= spec.width || y >= spec.height)
      throw UsageError{fmt::format(
          "--plot-pixel '{}': outside '{}', which is {}x{} (X 0..{}, Y "
          "0..{})",
          opt.plot_pixels[i], file, spec.width, spec.height, spec.width - 1, spec.height - 1)};
    // One row is read (a row of tiles for tiled files), not the whole image.
    in.read_rows(y, y + 1, row.data());
    const float* px = row.data() + static_cast<std::size_t>(x) * spec.nchannels;
    PlotCurve curve;
    curve.label = fmt::format("pixel ({}, {})", x, y);
    curve.wavelengths = layout.wavelengths;
    std::size_t bad = 0;
    for (int c : layout.band_channels) {
      const float v = px[c];
      bad += !std::isfinite(v);
      curve.values.push_back(std::isfinite(v) ? v : 0.0);
    }
    if (bad > 0 && opt.verbosity > 0)
      fmt::print(stderr,
                 "spectralize WARNING: '{}': pixel ({}, {}) has {} NaN/infinite samples, "
                 "drawn as 0\n",
                 file, x, y, bad);
    curve.colour = plot_palette(i);
    // The swatches: the file's own RGB (its previews, in the config's scene_linear space as
    // spectralize writes them by default) and the spectrum integrated as --to-rgb does.
    float rgb[4] = {0, 0, 0, 0};
    to_rgb.convert(px, spec.nchannels, 1, rgb, OIIO::TypeFloat);
    const Xyz from_spectrum = rgb_to_xyz(rgb[0], rgb[1], rgb[2]);
    const Xyz from_file = has_rgb ? rgb_to_xyz(px[r_ch], px[g_ch], px[b_ch]) : from_spectrum;
    // One exposure for both (the brighter fits), so a preview on another scale than its
    // spectrum shows as such.
    const double k = std::min(swatch.exposure(from_file), swatch.exposure(from_spectrum));
    scaled = scaled || k < 1;
    if (has_rgb) curve.swatches.push_back(swatch(from_file, k));
    curve.swatches.push_back(swatch(from_spectrum, k));
    plot.curves.push_back(std::move(curve));
  }
  const std::string name = fs::path(file).filename().string();
  plot.title.push_back(pixels.size() == 1 ? fmt::format("Pixel ({}, {}) of '{}'", pixels[0].first,
                                                        pixels[0].second, name)
                                          : fmt::format("{} pixels of '{}'", pixels.size(), name));
  plot.title.push_back(
      fmt::format("{}x{} | {} {} channels | {} bands {:g}-{:g} nm{}", spec.width, spec.height,
                  layout.emissive ? "emissive" : "reflective", layout.emissive ? "S0" : "T",
                  layout.wavelengths.size(), layout.wavelengths.front(), layout.wavelengths.back(),
                  layout.polarised ? " | polarised (S0 shown, S1-S3 ignored)" : ""));
  plot.title.push_back(fmt::format("swatches: {}{} -> {}", observer,
                                   layout.emissive ? "" : " under " + illuminant, cs.encoded));
  plot.notes.push_back("swatches: " + cs.encoded + " via OCIO");
  if (scaled) plot.notes.push_back("bright lights scaled to fit");
  apply_scale(opt, plot);
  if (csv) {
    AtomicOutput out(opt.output, WriteRules::named("the plot (-o)").streams(),
                     std::span<const std::string>(&file, 1));
    out.write(plot_csv(plot));
    out.commit();
    return kExitOk;
  }
  warn(write_plot(plot, opt.output, cs, std::span<const std::string>(&file, 1)));
  report(opt, plot);
  return kExitOk;
}

}  // namespace spectralize::tool
