#include "figures/figures.h"

#include <fmt/core.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "colour/colour_space.h"
#include "figures/figure_image.h"
#include "figures/sphere_render.h"
#include "plot/spectrum_plot.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"

namespace fs = std::filesystem;

namespace spectralize::figures {

namespace {

// The paper's examples (Zhdanov & Potemin): a light in lumens and a diffuse surface, both in
// Linear Rec.709.
constexpr Rgb kPaperLight{6000, 5000, 1000};
constexpr Rgb kPaperSurface{0.21, 0.72, 0.15};

// What every sphere figure shares: the working space, the geometry and the fixed calibration.
struct Stage {
  const ColourSpaces& spaces;
  Mat3 rgb_to_xyz, xyz_to_rgb;
  SphereGeometry geometry;
  std::string outdir;
  std::ostream& out;
};

// One scene rendered both ways.
struct Scene {
  std::string name, light, title;
  Rgb albedo, light_rgb;            // the RGB renderer's inputs
  std::vector<double> reflectance;  // the spectral renderer's: rho per band ...
  std::vector<Xyz> band_weights;    // ... and the light folded into the observer's weights
  Xyz calibration{1, 1, 1};         // diagonal on the spectral render's XYZ
  Xyz white;                        // CIELAB reference: a white sphere's centre
};

std::string path_in(const Stage& s, const std::string& file) {
  return (fs::path(s.outdir) / file).string();
}

// Display sRGB of an XYZ colour for the plot's swatches, scaled by k.
PlotColour swatch(const ColourSpaces& spaces, const Xyz& xyz, double k) {
  float rgb[3] = {static_cast<float>(k * xyz.X), static_cast<float>(k * xyz.Y),
                  static_cast<float>(k * xyz.Z)};
  spaces.from_xyz("sRGB - Texture").apply(rgb, 1);
  auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; };
  return {unit(rgb[0]), unit(rgb[1]), unit(rgb[2])};
}

// The largest linear working-space component of an image (for the exposure).
double brightest(const Stage& s, const std::vector<Xyz>& xyz) {
  double m = 0;
  for (const Xyz& v : xyz) {
    const Rgb c = to_rgb(s.xyz_to_rgb, v);
    m = std::max({m, c.r, c.g, c.b});
  }
  return m;
}

SphereFigure render(const Stage& s, const Scene& scene) {
  const std::vector<Xyz> rgb = render_rgb(s.geometry, scene.albedo, scene.light_rgb, s.rgb_to_xyz);
  const std::vector<Xyz> spectral =
      render_spectral(s.geometry, scene.reflectance, scene.band_weights, scene.calibration);
  const std::vector<Xyz> split = split_halves(s.geometry.size, rgb, spectral);
  const MirrorDifference d = mirror_delta_e(s.geometry, split, scene.white);

  // One exposure for both halves: the brightest channel maps to at most display white.
  SphereView view;
  view.exposure = 1 / std::max(1.0, brightest(s, split));
  write_sphere_png(path_in(s, scene.name + ".png"), s.geometry, split, view, s.spaces);
  write_delta_e_png(path_in(s, scene.name + "_dE.png"), s.geometry, d, kDeltaEMapScale,
                    fmt::format("{}: max dE2000 {:.3g}, mean {:.3g}", scene.title, d.max, d.mean));

  // The reflected colour at n.v = 1 of each renderer, in the working space.
  const Rgb a{scene.albedo.r * scene.light_rgb.r, scene.albedo.g * scene.light_rgb.g,
              scene.albedo.b * scene.light_rgb.b};
  Xyz w;
  for (std::size_t i = 0; i < scene.reflectance.size(); ++i)
    w = w + scene.reflectance[i] * scene.band_weights[i];
  const Rgb b = to_rgb(s.xyz_to_rgb, hadamard(w, scene.calibration));
  fmt::print(s.out,
             "{}: max dE2000 {:.3g} (mean {:.3g} over {} mirror pixel pairs; {}; reflected "
             "RGB {:.4g},{:.4g},{:.4g} (RGB render) vs {:.4g},{:.4g},{:.4g} (spectral render))\n",
             scene.name, d.max, d.mean, d.pairs, scene.title, a.r, a.g, a.b, b.r, b.g, b.b);
  return {scene.name, scene.light, d.max, d.mean, d.pairs};
}

// Fig. 1 / fig. 3: the spectrum of a colour, with the smooth model beside the paper's when it
// is available (it is an extension; the paper's spectrum is the figure's subject).
void plot_spectrum(const Stage& s, const std::string& file, const std::string& title,
                   const Rgb& rgb, const SpectralizerSettings& settings,
                   const SpectrumResult& paper) {
  SpectrumPlot plot;
  const bool light = settings.mode == Mode::emission;
  // ASCII only: OIIO 2.4's render_text draws other characters as '?'.
  plot.title = {
      title,
      fmt::format("{}, {}, {} nm, {}, filter {}", kDefaultColourSpace,
                  light ? "emission" : "reflectance under " + settings.illuminant,
                  settings.grid.to_string(), settings.observer, settings.filter.to_string()),
      fmt::format("relative XYZ error {:.2g}, L = {}, K = {}", paper.relative_error,
                  paper.detail("admissible"), paper.detail("dropped"))};
  plot.y_label = light ? "relative spectral radiance" : "reflectance";
  plot.y_top_at_least = light ? 0 : 1;
  plot.swatch_labels = {"input"};
  const Xyz input = mul(s.rgb_to_xyz, rgb);
  const double k = 1 / std::max({1.0, rgb.r, rgb.g, rgb.b});
  std::vector<double> nm;
  for (std::size_t i = 0; i < settings.grid.size(); ++i) nm.push_back(settings.grid[i]);
  plot.curves.push_back({"paper model (filter " + settings.filter.to_string() + ")",
                         nm,
                         paper.values,
                         plot_palette(0),
                         {swatch(s.spaces, input, k)}});
  // The models beyond the paper on the same colour, for comparison.
  int colour = 1;
  for (const char* model : {"smooth", "natural"}) {
    try {
      SpectralizerSettings other = settings;
      other.model = model;
      const SpectrumResult r = Spectralizer(other).spectralize(input);
      if (r.status == Outcome::exact)
        plot.curves.push_back({std::string(model) + " model",
                               nm,
                               r.values,
                               plot_palette(colour),
                               {swatch(s.spaces, input, k)}});
    } catch (const Error& e) {
      fmt::print(s.out, "{}: {} model unavailable ({}); not plotted\n", file, model, e.what());
    }
    ++colour;
  }
  if (light) plot.notes.push_back("swatch scaled to display white");
  for (const std::string& w : write_plot(plot, path_in(s, file), plot_spaces(s.spaces)))
    fmt::print(s.out, "{}: {}\n", file, w);
}

}  // namespace

std::vector<SphereFigure> make_figures(const std::string& outdir, std::ostream& out) {
  std::error_code ec;
  fs::create_directories(outdir, ec);
  if (ec) throw Error("cannot create the output folder '" + outdir + "': " + ec.message());

  const ColourSpaces spaces = ColourSpaces::load();
  const Mat3 m = rgb_to_xyz_matrix(spaces, kDefaultColourSpace);
  Stage s{spaces,
          m,
          xyz_to_rgb_matrix(spaces, kDefaultColourSpace),
          SphereGeometry::orthographic(kSphereSize, kSphereSupersample),
          outdir,
          out};

  // The paper's two spectra, by the paper's model (with its default edge filter).
  SpectralizerSettings light_settings;
  light_settings.model = "paper";
  light_settings.mode = Mode::emission;
  const Spectralizer light_sp(light_settings);
  const SpectrumResult light = light_sp.spectralize(mul(m, kPaperLight));
  SpectralizerSettings surface_settings;
  surface_settings.model = "paper";
  surface_settings.mode = Mode::reflectance;
  const Spectralizer surface_sp(surface_settings);
  const SpectrumResult surface = surface_sp.spectralize(mul(m, kPaperSurface));
  if (light.status != Outcome::exact || surface.status != Outcome::exact)
    throw Error("the paper's colours did not spectralize exactly: " + light.message + " " +
                surface.message);

  plot_spectrum(s, "fig1_light_spectrum.png", "The paper's light: RGB (6000, 5000, 1000) lm",
                kPaperLight, light_settings, light);
  plot_spectrum(s, "fig3_surface_spectrum.png", "The paper's surface: RGB (0.21, 0.72, 0.15)",
                kPaperSurface, surface_settings, surface);

  std::vector<SphereFigure> figures;
  // Fig. 2: a white sphere lit by the light. Emission weights (normalised by K) times the
  // light's spectrum give the light's XYZ in its own units; no calibration.
  {
    Scene scene{"fig2_sphere_light",
                "paper light",
                "white sphere, light RGB (6000, 5000, 1000)",
                {1, 1, 1},
                kPaperLight,
                std::vector<double>(light.values.size(), 1.0),
                light_sp.weights().columns(),
                {1, 1, 1},
                mul(m, kPaperLight)};
    for (std::size_t i = 0; i < scene.band_weights.size(); ++i)
      scene.band_weights[i] = light.values[i] * scene.band_weights[i];
    figures.push_back(render(s, scene));
  }

  // Figs. 4-6: the surface under D65, A and FL11. Reflectance weights under each light are
  // normalised so rho == 1 has Y = 1 (lights of equal luminance). One fixed calibration for
  // all three, the project's white balance (docs/DESIGN.md §3): rho == 1 under D65 is RGB (1, 1,
  // 1). No adaptation to A or FL11: both halves show the light's colour, as an RGB renderer whose
  // light is that illuminant's colour does.
  const Observer& observer = Observer::get(surface_settings.observer);
  const Illuminant d65 = Illuminant::get("D65");
  const Xyz d65_white = SampleWeights(surface_settings.grid, observer, &d65).unit_white();
  const Xyz calibration = balance_to_d65(d65_white);
  const struct {
    const char* name;
    const char* light;
    const char* title;
  } lights[] = {{"fig4_sphere_surface", "D65", "surface (0.21, 0.72, 0.15) under D65"},
                {"fig5_sphere_surface_A", "A", "same surface under illuminant A"},
                {"fig6_sphere_surface_F11", "FL11", "same surface under fluorescent F11"}};
  for (const auto& l : lights) {
    const Illuminant illuminant = Illuminant::get(l.light);
    const SampleWeights w(surface_settings.grid, observer, &illuminant);
    const Xyz white = hadamard(w.unit_white(), calibration);
    // The RGB renderer's light: the illuminant's colour in the working space (Y = 1).
    const Rgb light_rgb = to_rgb(s.xyz_to_rgb, white);
    figures.push_back(render(s, {l.name, l.light, l.title, kPaperSurface, light_rgb, surface.values,
                                 w.columns(), calibration, white}));
  }
  return figures;
}

}  // namespace spectralize::figures
