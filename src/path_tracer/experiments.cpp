#include "path_tracer/experiments.h"

#include <spectralize/rt.h>
#include <spectralize/rt.hpp>

#include <fmt/core.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "baseline/sigmoid_spectrum.h"
#include "colour/colour_space.h"
#include "figures/figure_image.h"
#include "path_tracer/environment.h"
#include "path_tracer/render.h"
#include "path_tracer/rt_texture.h"
#include "path_tracer/sampled_spectra.h"
#include "path_tracer/scene_inputs.h"
#include "path_tracer/sigmoid_texture.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

namespace {

using TablePtr = std::unique_ptr<spz_table, decltype(&spz_table_free)>;

// A table file of the wanted mode (1 reflectance, 0 emission), or Error with rt's message.
TablePtr load_table(const std::string& path, int mode) {
  char error[512] = "";
  TablePtr t(spz_table_load(path.c_str(), error, sizeof error), &spz_table_free);
  if (!t) throw Error(error);
  if (spz_table_mode(t.get()) != mode)
    throw Error("'" + path + "': a table of " + (mode ? "emission" : "reflectance") + ", not of " +
                (mode ? "reflectance" : "emission"));
  return t;
}

// The comparison's truth is the measured ColorChecker, and near the chart's colours the exemplar
// model's spectra are those measurements (its exemplars, docs/DESIGN.md §6): a table of it would
// be compared with the data it was made from. Error for such a table. Cost: O(1).
void require_unseen_truth(const spz_table* table, const std::string& path) {
  const std::string model = table->table.view().header().model;
  if (model == "exemplar")
    throw Error("'" + path + "': a table of the exemplar model, whose exemplars include the " +
                "measured ColorChecker the comparison renders as its truth; make the table with " +
                "--model natural (a model that has not seen the chart)");
}

// Samples per pixel of the floor's renders (it is the same at any count).
constexpr int kFloorSpp = 16;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Display exposure of a scene: its upward white at 0.8 of display white.
double exposure_of(const Xyz& white) {
  return 0.8 / white.Y;
}

std::vector<bool> covered(const RenderResult& r, bool fully) {
  std::vector<bool> m(r.coverage.size());
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = fully ? r.coverage[i] == 1 : r.coverage[i] > 0;
  return m;
}

nlohmann::json stats_json(const DeltaEStats& s) {
  return {{"mean", s.mean}, {"p95", s.p95}, {"max", s.max}, {"pixels", s.pixels}};
}

}  // namespace

ConvergenceReport run_convergence(const ConvergenceSetup& s) {
  const auto t0 = std::chrono::steady_clock::now();
  const ColourSpaces spaces = ColourSpaces::load();
  const TablePtr reflectance = load_table(s.reflectance_table, 1);
  const TablePtr emission = load_table(s.emission_table, 0);
  const RgbImage texture =
      read_linear_rgb(s.texture, s.texture_space, spz_table_colorspace(reflectance.get()), spaces);
  const RgbImage env_rgb = read_linear_rgb(s.environment, s.environment_space,
                                           spz_table_colorspace(emission.get()), spaces);
  std::vector<Xyz> env_xyz =
      texel_xyz(env_rgb, figures::rgb_to_xyz_matrix(spaces, spz_table_colorspace(emission.get())));
  for (Xyz& v : env_xyz) v = static_cast<double>(s.light_scale) * v;
  const Environment environment(env_rgb.width, env_rgb.height, std::move(env_xyz));
  const Scene scene(s.render.layout, texture.width, texture.height);
  const SpectralFilm film(Observer::get("cie1931"));

  const RtTexture rt_surface(reflectance.get(), texture.rgb);
  const RtTexture rt_light(emission.get(), env_rgb.rgb, s.light_scale);
  const SampledSpectra dense_surface = SampledSpectra::read_exr(s.texture_spectra);
  const SampledSpectra dense_light = SampledSpectra::read_exr(s.environment_spectra, s.light_scale);
  if (dense_surface.emissive())
    throw Error("'" + s.texture_spectra + "': emissive (S0) spectra, not a texture's reflectances");
  if (!dense_light.emissive())
    throw Error("'" + s.environment_spectra + "': reflective (T) spectra, not a light's");
  if (dense_surface.texels() != rt_surface.texels() || dense_light.texels() != rt_light.texels())
    throw Error("the spectral files are not the size of the RGB images ('" + s.texture_spectra +
                "', '" + s.environment_spectra + "')");

  const SpectralRender renders[] = {{"rt", &rt_surface, &rt_light, false},
                                    {"reference", &dense_surface, &dense_light, true}};
  const RenderResult r =
      render(scene, environment, film, renders, s.render.size, s.render.spp, s.render.threads);
  // The floor does not depend on the sample count: rt's spectra over all wavelengths against the
  // reference on the same few paths.
  const SpectralRender exact[] = {{"reference", &dense_surface, &dense_light, true},
                                  {"rt_all_wavelengths", &rt_surface, &rt_light, true}};
  const int floor_spp = std::min(s.render.spp.back(), kFloorSpp);
  const RenderResult f =
      render(scene, environment, film, exact, s.render.size, {floor_spp}, s.render.threads);

  ConvergenceReport report;
  report.white = environment.white_up();
  const std::size_t last = r.spp.size() - 1;
  for (std::size_t k = 0; k < r.spp.size(); ++k)
    report.points.push_back(
        {r.spp[k], summarize(delta_e_map(r.images[0][k], r.images[1][k], report.white))});
  report.floor = summarize(delta_e_map(f.images[1][0], f.images[0][0], report.white));
  report.floor_spp = floor_spp;
  for (std::size_t i = 0; i < f.images[0][0].size(); ++i)
    report.floor_relative_xyz =
        std::max(report.floor_relative_xyz,
                 (f.images[1][0][i] - f.images[0][0][i]).max_abs() / report.white.Y);
  report.mapped = rt_surface.mapped() + rt_light.mapped();
  report.invalid = rt_surface.invalid() + rt_light.invalid();

  if (!s.render.png_prefix.empty()) {
    const std::string& p = s.render.png_prefix;
    const double exposure = exposure_of(report.white);
    const int n = s.render.size;
    figures::write_xyz_png(p + "_rt.png", n, n, r.images[0][last], exposure, spaces,
                           "rt, " + std::to_string(r.spp[last]) + " spp");
    figures::write_xyz_png(p + "_reference.png", n, n, r.images[1][last], exposure, spaces,
                           "dense reference");
    const std::vector<bool> all(static_cast<std::size_t>(n) * n, true);
    for (const std::size_t k : {std::size_t{0}, last}) {
      const std::vector<double> de = delta_e_map(r.images[0][k], r.images[1][k], report.white);
      const DeltaEStats st = summarize(de);
      figures::write_delta_e_map_png(
          p + "_dE_" + std::to_string(r.spp[k]) + "spp.png", n, de, all, 2.0,
          fmt::format("{} spp: mean {:.2f}, p95 {:.2f}", r.spp[k], st.mean, st.p95));
    }
  }
  report.seconds = seconds_since(t0);
  return report;
}

ComparisonReport run_comparison(const ComparisonSetup& s) {
  const auto t0 = std::chrono::steady_clock::now();
  const ColourSpaces spaces = ColourSpaces::load();
  const TablePtr reflectance = load_table(s.reflectance_table, 1);
  require_unseen_truth(reflectance.get(), s.reflectance_table);
  const std::string space = spz_table_colorspace(reflectance.get());
  const RgbImage texture = read_linear_rgb(s.texture, s.texture_space, space, spaces);
  const figures::Mat3 m = figures::rgb_to_xyz_matrix(spaces, space);

  // The light: the illuminant's spectrum at Y = 1, times the map's luminance per texel.
  const RgbImage pattern = read_linear_rgb(s.environment, s.environment_space, space, spaces);
  Xyz unit_xyz;
  std::vector<float> spd = unit_illuminant(s.illuminant, &unit_xyz);
  std::vector<Xyz> env_xyz = texel_xyz(pattern, m);
  std::vector<float> luminance(env_xyz.size());
  for (std::size_t i = 0; i < env_xyz.size(); ++i) {
    luminance[i] = static_cast<float>(std::max(0.0, env_xyz[i].Y));
    env_xyz[i] = static_cast<double>(luminance[i]) * unit_xyz;
  }
  const Environment environment(pattern.width, pattern.height, std::move(env_xyz));
  const SampledSpectra light(static_cast<float>(ReferenceTable::kStartNm), 1.0f,
                             ReferenceTable::kSize, std::move(spd),
                             std::vector<std::uint32_t>(luminance.size(), 0), luminance);

  const SampledSpectra truth = with_context(
      "'" + s.texture + "'", [&] { return measured_colorchecker(texture.width, texture.height); });
  const RtTexture rt(reflectance.get(), texture.rgb);
  baseline::RgbToXyz rgb_to_xyz;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rgb_to_xyz[r][c] = m[r][c];
  const baseline::SigmoidFitter fitter(rgb_to_xyz);
  const baseline::SigmoidTable table(fitter, s.sigmoid_resolution, s.render.threads);
  const SigmoidTexture sigmoid(table, texture.rgb);

  const Scene scene(s.render.layout, texture.width, texture.height);
  const SpectralFilm film(Observer::get("cie1931"));
  const SpectralRender renders[] = {{"truth", &truth, &light, false},
                                    {"rt", &rt, &light, false},
                                    {"baseline", &sigmoid, &light, false}};
  const std::vector<int> spp{s.render.spp.back()};
  const RenderResult r =
      render(scene, environment, film, renders, s.render.size, spp, s.render.threads);

  ComparisonReport report;
  report.illuminant = s.illuminant;
  report.spp = spp.back();
  const Xyz white = environment.white_up();
  const std::vector<bool> surfaces = covered(r, true);
  const std::vector<double> rt_de = delta_e_map(r.images[1][0], r.images[0][0], white);
  const std::vector<double> base_de = delta_e_map(r.images[2][0], r.images[0][0], white);
  report.rt_vs_truth = summarize(rt_de, surfaces);
  report.baseline_vs_truth = summarize(base_de, surfaces);
  report.rt_vs_baseline = summarize(delta_e_map(r.images[1][0], r.images[2][0], white), surfaces);
  report.mapped = rt.mapped();
  report.sigmoid_max_node_delta_e76 = table.max_node_delta_e();

  if (!s.render.png_prefix.empty()) {
    const std::string& p = s.render.png_prefix;
    const double exposure = exposure_of(white);
    const int n = s.render.size;
    const std::string light_name = "illuminant " + s.illuminant;
    figures::write_xyz_png(p + "_truth.png", n, n, r.images[0][0], exposure, spaces,
                           "measured, " + light_name);
    figures::write_xyz_png(p + "_rt.png", n, n, r.images[1][0], exposure, spaces,
                           "spectralize::rt");
    figures::write_xyz_png(p + "_baseline.png", n, n, r.images[2][0], exposure, spaces,
                           "Jakob-Hanika " + std::to_string(s.sigmoid_resolution) + "^3");
    const std::vector<bool> shown = covered(r, false);
    figures::write_delta_e_map_png(p + "_rt_dE.png", n, rt_de, shown, s.map_scale,
                                   fmt::format("rt: mean {:.2f}, p95 {:.2f}",
                                               report.rt_vs_truth.mean, report.rt_vs_truth.p95));
    figures::write_delta_e_map_png(
        p + "_baseline_dE.png", n, base_de, shown, s.map_scale,
        fmt::format("baseline: mean {:.2f}, p95 {:.2f}", report.baseline_vs_truth.mean,
                    report.baseline_vs_truth.p95));
  }
  report.seconds = seconds_since(t0);
  return report;
}

std::string to_json(const ConvergenceReport& r) {
  nlohmann::json points = nlohmann::json::array();
  for (const ConvergencePoint& p : r.points)
    points.push_back({{"spp", p.spp}, {"rt_vs_reference", stats_json(p.rt)}});
  return nlohmann::json{{"convergence", points},
                        {"floor", stats_json(r.floor)},
                        {"floor_spp", r.floor_spp},
                        {"floor_relative_xyz", r.floor_relative_xyz},
                        {"mapped_lookups", r.mapped},
                        {"invalid_lookups", r.invalid},
                        {"white", {r.white.X, r.white.Y, r.white.Z}},
                        {"seconds", r.seconds}}
      .dump(2);
}

std::string to_json(const ComparisonReport& r) {
  return nlohmann::json{{"illuminant", r.illuminant},
                        {"spp", r.spp},
                        {"rt_vs_truth", stats_json(r.rt_vs_truth)},
                        {"baseline_vs_truth", stats_json(r.baseline_vs_truth)},
                        {"rt_vs_baseline", stats_json(r.rt_vs_baseline)},
                        {"mapped_lookups", r.mapped},
                        {"sigmoid_max_node_delta_e76", r.sigmoid_max_node_delta_e76},
                        {"seconds", r.seconds}}
      .dump(2);
}

}  // namespace spectralize::path_tracer
