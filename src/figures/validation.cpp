#include "figures/validation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/colorimetry/colour_difference.h"
#include "core/models/exemplar_model.h"
#include "core/tables/spectral_table.h"
#include "figures/reference_rows.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectrum_model.h"

namespace spectralize::figures {

namespace {

// The set's measured reflectances on the grid: the core's resampling (the exemplar model's
// own), refused where the data do not cover the grid (no extension by end values here).
std::vector<MeasuredPatch> load_patches(const PatchSet& set, const WavelengthGrid& grid) {
  const std::vector<std::string> names = embedded_columns(set.file);
  for (const std::string& name : names) {
    const auto [nm, values] = embedded_column(set.file, name);
    if (nm.front() > grid.start() || nm.back() < grid.end())
      throw Error("'" + set.file + "' covers " + std::to_string(nm.front()) + ".." +
                  std::to_string(nm.back()) + " nm, not the grid " + grid.to_string());
  }
  std::vector<double> wavelengths;
  for (std::size_t i = 0; i < grid.size(); ++i) wavelengths.push_back(grid[i]);
  std::vector<std::vector<double>> rho =
      development_reflectances(wavelengths, std::span<const std::string>(&set.file, 1));
  if (rho.size() != set.count || names.size() != set.count)
    throw Error("'" + set.file + "' has " + std::to_string(rho.size()) + " patches, expected " +
                std::to_string(set.count));
  std::vector<MeasuredPatch> patches;
  for (std::size_t k = 0; k < rho.size(); ++k) patches.push_back({names[k], std::move(rho[k])});
  return patches;
}

// An illuminant whose 1 nm table is the piecewise-linear spectrum `values` on `grid` (zero
// outside it): how a light given on the grid is applied to reflectances.
Illuminant light_on_table(const std::string& name, const WavelengthGrid& grid,
                          const std::vector<double>& values) {
  Illuminant il{name, std::vector<double>(ReferenceTable::kSize)};
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k)
    il.spd[k] = piecewise_linear(grid, values, ReferenceTable::wavelength(k));
  return il;
}

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

// Viewing conditions: XYZ of a reflectance under a light (rho == 1 has Y = 1) and its white.
struct Viewing {
  SampleWeights weights;
  Xyz white;
  Lab lab(const std::vector<double>& rho) const { return to_lab(weights.integrate(rho), white); }
};

Viewing viewing(const WavelengthGrid& grid, const Observer& obs, const Illuminant& light) {
  SampleWeights w(grid, obs, &light);
  const Xyz white = w.unit_white();
  return {std::move(w), white};
}

std::array<double, 3> triple(const Xyz& v) {
  return {v.X, v.Y, v.Z};
}

PatchResult run_patch(const Reconstruction& row, const Spectralizer& protocol,
                      const ColourTransform& to_xyz, const ColourTransform& from_xyz,
                      std::size_t set, std::size_t index, const MeasuredPatch& patch,
                      const Viewing& d65, const std::vector<Viewing>& lights) {
  PatchResult r;
  r.name = patch.name;
  // The patch's colour as an RGB texture holds it: under D65, relative to the reflected white
  // (the paper's eq. 6), in the space; clipped to [0, 1] when outside.
  const Xyz measured = d65.weights.integrate(patch.rho);
  const Xyz balanced = hadamard(measured, balance_to_d65(d65.white));
  Xyz rgb = from_xyz(balanced.X, balanced.Y, balanced.Z);
  for (int c = 0; c < 3; ++c) {
    const double clipped = std::clamp(rgb[c], 0.0, 1.0);
    r.clipped = r.clipped || clipped != rgb[c];
    rgb[c] = clipped;
  }
  r.rgb = triple(rgb);
  const Xyz input = to_xyz(rgb.X, rgb.Y, rgb.Z);
  const Reconstructed s = row.reconstruct(set, index, r.rgb, input);
  r.status = s.status;
  const std::vector<double>& rho = s.values;

  // Exactness by the reference integration itself, not the solver's weights.
  const SpectralizerSettings& settings = protocol.settings();
  const Xyz target = protocol.target_of(input);
  const Xyz xyz = integrate_reference(settings.grid, rho, protocol.observer(),
                                      protocol.illuminant(), d65.weights.normalisation());
  r.relative_xyz_error = relative_error(xyz, target);
  r.delta_e_d65 = delta_e_2000(to_lab(xyz, d65.white), to_lab(target, d65.white));
  r.delta_e_d65_measured = delta_e_2000(to_lab(xyz, d65.white), to_lab(measured, d65.white));
  for (const Viewing& light : lights)
    r.delta_e.push_back(delta_e_2000(light.lab(rho), light.lab(patch.rho)));
  r.rmse = rms_difference(rho, patch.rho);
  r.roughness = roughness(rho);
  r.roughness_measured = roughness(patch.rho);
  r.edge_ratio = edge_ratio(settings.grid, rho);
  r.edge_ratio_measured = edge_ratio(settings.grid, patch.rho);
  r.rho_min = *std::min_element(rho.begin(), rho.end());
  r.rho_max = *std::max_element(rho.begin(), rho.end());
  return r;
}

LightResult run_light(const Spectralizer& sp, const ColourTransform& to_xyz,
                      const ColourTransform& from_xyz, const std::string& name,
                      const std::vector<MeasuredPatch>& patches) {
  const SpectralizerSettings& settings = sp.settings();
  const WavelengthGrid& grid = settings.grid;
  LightResult r;
  r.name = name;
  // The real SPD sampled on the grid (the spectrum the reconstruction is compared with),
  // normalised to Y = 1.
  const Illuminant table = Illuminant::get(name);
  std::vector<double> real(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double u = grid[i] - ReferenceTable::kStartNm;  // position on the 1 nm table
    const std::size_t k = std::min(static_cast<std::size_t>(u), ReferenceTable::kSize - 2);
    const double t = u - static_cast<double>(k);
    real[i] = (1 - t) * table.spd[k] + t * table.spd[k + 1];
  }
  const double y_real = sp.weights().integrate(real).Y;
  for (double& v : real) v /= y_real;
  const Xyz xyz_real = sp.weights().integrate(real);

  // The light as RGB (no clipping: scene-linear light may be negative; counted).
  const Xyz rgb = from_xyz(xyz_real.X, xyz_real.Y, xyz_real.Z);
  r.rgb = triple(rgb);
  r.in_gamut = rgb.X >= 0 && rgb.Y >= 0 && rgb.Z >= 0;
  const SpectrumResult s = sp.spectralize(to_xyz(rgb.X, rgb.Y, rgb.Z));
  r.status = std::string(to_string(s.status));
  const Xyz xyz =
      integrate_reference(grid, s.values, sp.observer(), nullptr, sp.weights().normalisation());
  r.relative_xyz_error = relative_error(xyz, s.target);
  std::vector<double> phi = s.values;
  for (double& v : phi) v /= xyz.Y;

  // The light itself (exact up to OCIO's float maths), relative to the D65 white at Y = 1.
  r.delta_e_light = delta_e_2000(to_lab((1 / xyz.Y) * xyz, kWhiteD65), to_lab(xyz_real, kWhiteD65));
  r.rmse = rms_difference(phi, real);
  r.roughness = roughness(phi);
  r.roughness_real = roughness(real);
  r.edge_ratio = edge_ratio(grid, phi);

  // What matters for a light: the surfaces it shows. The ColorChecker under both lights,
  // each relative to its own white (equal here, by exactness).
  const Viewing lit_real = viewing(grid, sp.observer(), light_on_table(name, grid, real));
  const Viewing lit_recon = viewing(grid, sp.observer(), light_on_table(name, grid, phi));
  std::vector<double> de;
  for (const MeasuredPatch& p : patches)
    de.push_back(delta_e_2000(lit_recon.lab(p.rho), lit_real.lab(p.rho)));
  const Spread sd = spread(de);
  r.checker_delta_e_median = sd.median;
  r.checker_delta_e_max = sd.max;
  return r;
}

// The RGB renderer's view of each patch under each light: RGB (as run_patch makes it) times
// the light's RGB, against the measurement. Both in the frame of the fixed D65 calibration
// (rho == 1 under D65 is RGB 1, 1, 1); CIELAB is unchanged by that diagonal scaling.
RgbBaseline rgb_baseline(const std::string& space, const std::string& set,
                         const ColourTransform& to_xyz, const ColourTransform& from_xyz,
                         const std::vector<MeasuredPatch>& patches, const Viewing& d65,
                         const std::vector<Viewing>& lights) {
  const Xyz calibration = balance_to_d65(d65.white);
  RgbBaseline b;
  b.space = space;
  b.set = set;
  auto render = [&](const MeasuredPatch& p, const Viewing& light) {
    const Xyz balanced = hadamard(d65.weights.integrate(p.rho), calibration);
    Xyz rgb = from_xyz(balanced.X, balanced.Y, balanced.Z);
    for (int c = 0; c < 3; ++c) rgb[c] = std::clamp(rgb[c], 0.0, 1.0);
    const Xyz white = hadamard(light.white, calibration);
    const Xyz light_rgb = from_xyz(white.X, white.Y, white.Z);
    const Xyz shown = to_xyz(rgb.X * light_rgb.X, rgb.Y * light_rgb.Y, rgb.Z * light_rgb.Z);
    const Xyz truth = hadamard(light.weights.integrate(p.rho), calibration);
    return delta_e_2000(to_lab(shown, white), to_lab(truth, white));
  };
  for (const MeasuredPatch& p : patches) b.patches.push_back(p.name);
  for (const Viewing& light : lights) {
    std::vector<double> de;
    for (const MeasuredPatch& p : patches) de.push_back(render(p, light));
    b.spreads.push_back(spread(de));
    b.delta_e.push_back(std::move(de));
  }
  return b;
}

ValidationSummary summarise(const std::vector<PatchResult>& patches, std::size_t lights) {
  ValidationSummary s;
  std::vector<double> d65;
  std::vector<std::vector<double>> under(lights);
  s.rho_min = INFINITY;
  s.rho_max = -INFINITY;
  for (const PatchResult& p : patches) {
    d65.push_back(p.delta_e_d65);
    for (std::size_t k = 0; k < lights; ++k) under[k].push_back(p.delta_e[k]);
    s.mean_rmse += p.rmse / static_cast<double>(patches.size());
    s.mean_roughness += p.roughness / static_cast<double>(patches.size());
    s.mean_roughness_measured += p.roughness_measured / static_cast<double>(patches.size());
    s.max_relative_xyz_error = std::max(s.max_relative_xyz_error, p.relative_xyz_error);
    s.max_edge_ratio = std::max(s.max_edge_ratio, p.edge_ratio);
    s.max_edge_ratio_measured = std::max(s.max_edge_ratio_measured, p.edge_ratio_measured);
    s.rho_min = std::min(s.rho_min, p.rho_min);
    s.rho_max = std::max(s.rho_max, p.rho_max);
    s.clipped += p.clipped ? 1 : 0;
  }
  s.delta_e_d65 = spread(d65);
  for (auto& v : under) s.delta_e.push_back(spread(std::move(v)));
  return s;
}

// A registered model's reconstruction: the Spectralizer in reflectance mode.
class ModelReconstruction final : public Reconstruction {
 public:
  explicit ModelReconstruction(const SpectralizerSettings& settings) : sp_(settings) {}
  Reconstructed reconstruct(std::size_t, std::size_t, const std::array<double, 3>&,
                            const Xyz& xyz_d65) const override {
    SpectrumResult r = sp_.spectralize(xyz_d65);
    return {std::move(r.values), std::string(to_string(r.status))};
  }

 private:
  Spectralizer sp_;
};

// A registered model through the render-time table of the space (docs/DESIGN.md §14): the
// blend of the cell's node spectra that images, --color and a renderer's table file give,
// in the frame of the space's primaries (its linear RGB -> XYZ, read off the transform).
class TableReconstruction final : public Reconstruction {
 public:
  TableReconstruction(const SpectralizerSettings& settings, const RowContext& context)
      : sp_(settings), table_(sp_, SpectralTable::Method::table, frame_of(*context.to_xyz)) {}
  Reconstructed reconstruct(std::size_t, std::size_t, const std::array<double, 3>&,
                            const Xyz& xyz_d65) const override {
    std::vector<float> values(sp_.settings().grid.size());
    PixelResult pixel;
    table_.spectra(&xyz_d65, 1, values.data(), &pixel);
    const Outcome status = pixel.kind;
    return {std::vector<double>(values.begin(), values.end()), std::string(to_string(status))};
  }

 private:
  static Mat3 frame_of(const ColourTransform& to_xyz) {
    Mat3 m{};
    for (int c = 0; c < 3; ++c) {
      const Xyz col = to_xyz(c == 0, c == 1, c == 2);
      m[c] = col.X, m[3 + c] = col.Y, m[6 + c] = col.Z;
    }
    return m;
  }
  Spectralizer sp_;
  mutable SpectralTable table_;  // builds its cells on first use
};

// The exemplar model, cross-validated: its exemplars are the development sets, so each set is
// scored with the other set as the library (else every patch would find its own measurement).
// Built on the protocol's weights; the patches' colours are inside the solid, as the model
// requires (no gamut mapping needed).
class CrossValidatedExemplar final : public Reconstruction {
 public:
  explicit CrossValidatedExemplar(const RowContext& context) : protocol_(*context.protocol) {
    const WavelengthGrid& grid = protocol_.settings().grid;
    for (std::size_t i = 0; i < grid.size(); ++i) nm_.push_back(grid[i]);
    ModelContext mc;
    mc.columns = protocol_.weights().columns();
    mc.wavelengths = nm_;
    mc.step_nm = grid.step();
    for (const PatchSet& scored : validation_sets()) {
      std::vector<std::string> others;
      for (const std::string& file : development_set_files())
        if (file != scored.file) others.push_back(file);
      models_.push_back(std::make_unique<ExemplarModel>(mc, development_reflectances(nm_, others)));
    }
  }
  Reconstructed reconstruct(std::size_t set, std::size_t, const std::array<double, 3>&,
                            const Xyz& xyz_d65) const override {
    ModelSolution s = models_.at(set)->solve(protocol_.target_of(xyz_d65), 1.0);
    for (double& v : s.values) v = std::clamp(v, 0.0, 1.0);
    return {std::move(s.values), s.converged ? "ok" : "not_converged"};
  }

 private:
  const Spectralizer& protocol_;
  std::vector<double> nm_;
  std::vector<std::unique_ptr<ExemplarModel>> models_;  // per validation set: the others' exemplars
};

SpectralizerSettings model_settings(const RegisteredModel& model, const EdgeFilter& filter,
                                    Mode mode) {
  SpectralizerSettings settings;
  settings.model = model;
  settings.filter = filter;
  settings.mode = mode;
  return settings;
}

ValidationConfig model_row(std::string name, std::string model, EdgeFilter filter) {
  ValidationConfig c{std::move(name), model, filter, true, {}};
  c.make = [model, filter](const RowContext&) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<ModelReconstruction>(model_settings(model, filter, Mode::reflectance));
  };
  return c;
}

ValidationConfig table_row(std::string name, std::string model) {
  ValidationConfig c{std::move(name), model, default_edge_filter(), true, {}};
  c.make = [model](const RowContext& context) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<TableReconstruction>(
        model_settings(model, default_edge_filter(), Mode::reflectance), context);
  };
  return c;
}

ValidationConfig exemplar_row(std::string name) {
  ValidationConfig c{std::move(name), "exemplar", default_edge_filter(), true, {}};
  c.make = [](const RowContext& context) -> std::unique_ptr<Reconstruction> {
    return std::make_unique<CrossValidatedExemplar>(context);
  };
  return c;
}

}  // namespace

std::vector<std::string> validation_lights() {
  return {"A", "FL11", "FL2", "LED-B3", "HP1", "D50"};
}

std::vector<ValidationConfig> validation_configs() {
  const std::string def(default_model_name());
  auto tag = [&](const std::string& model) { return model == def ? " (default)" : ""; };
  std::vector<ValidationConfig> rows = {
      model_row("paper, filter " + default_edge_filter().to_string() + tag("paper"), "paper",
                default_edge_filter()),
      model_row("paper, filter 0.5", "paper", EdgeFilter::parse("0.5")),
      model_row("paper, filter 0.9", "paper", EdgeFilter::parse("0.9")),
      model_row("smooth" + std::string(tag("smooth")), "smooth", default_edge_filter()),
      model_row("natural" + std::string(tag("natural")), "natural", default_edge_filter()),
      table_row("natural, render-time table", "natural"),
      exemplar_row(std::string("exemplar") + (def == "exemplar" ? " (default;" : " (") +
                   " cross-validated: each set with the other's exemplars)")};
  for (ValidationConfig& r : reference_rows()) rows.push_back(std::move(r));
  return rows;
}

std::vector<std::string> validation_spaces() {
  return {"Linear Rec.709 (sRGB)", "Linear Rec.2020"};
}

std::vector<PatchSet> validation_sets() {
  const std::vector<std::string> files = development_set_files();  // ColorChecker first
  return {{"ColorChecker", files.at(0), 24}, {"AMPAS 190", files.at(1), 190}};
}

Spread spread(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const double pos = q * static_cast<double>(v.size() - 1);
    const std::size_t i = static_cast<std::size_t>(pos);
    if (i + 1 >= v.size()) return v.back();
    return v[i] + (pos - static_cast<double>(i)) * (v[i + 1] - v[i]);
  };
  return {at(0.5), at(0.95), v.back()};
}

double roughness(const std::vector<double>& x) {
  if (x.size() < 3) return 0;
  double s = 0;
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    const double d2 = x[i - 1] - 2 * x[i] + x[i + 1];
    s += d2 * d2;
  }
  return std::sqrt(s / static_cast<double>(x.size() - 2));
}

double edge_ratio(const WavelengthGrid& grid, const std::vector<double>& x) {
  double edge = 0, interior = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (grid[i] <= grid.start() + 20 || grid[i] >= grid.end() - 20) edge = std::max(edge, x[i]);
    if (grid[i] >= 400 && grid[i] <= 700) {
      interior += x[i];
      ++n;
    }
  }
  return n && interior > 0 ? edge / (interior / static_cast<double>(n)) : 0.0;
}

std::vector<std::vector<MeasuredPatch>> load_validation_sets() {
  const SpectralizerSettings defaults;
  std::vector<std::vector<MeasuredPatch>> sets;
  for (const PatchSet& set : validation_sets()) sets.push_back(load_patches(set, defaults.grid));
  return sets;
}

Validation validate(const ColourSpaces& spaces) {
  const SpectralizerSettings defaults;
  const Observer& obs = Observer::get(defaults.observer);
  const std::vector<std::vector<MeasuredPatch>> sets = load_validation_sets();
  const std::vector<MeasuredPatch>& checker = sets.front();
  const Viewing d65 = viewing(defaults.grid, obs, Illuminant::get("D65"));
  std::vector<Viewing> lights;
  for (const std::string& light : validation_lights())
    lights.push_back(viewing(defaults.grid, obs, Illuminant::get(light)));
  // The protocol's own targets and weights (the default settings, reflectance mode).
  const Spectralizer protocol(model_settings(defaults.model, defaults.filter, Mode::reflectance));

  Validation results;
  for (const std::string& space : validation_spaces())
    for (std::size_t k = 0; k < sets.size(); ++k)
      results.baselines.push_back(rgb_baseline(space, validation_sets()[k].name,
                                               spaces.to_xyz(space), spaces.from_xyz(space),
                                               sets[k], d65, lights));
  for (const ValidationConfig& config : validation_configs())
    for (const std::string& space : validation_spaces()) {
      ConfigResult c;
      c.config = config;
      c.space = space;
      const auto start = std::chrono::steady_clock::now();
      try {
        const ColourTransform to_xyz = spaces.to_xyz(space);
        const ColourTransform from_xyz = spaces.from_xyz(space);
        const std::unique_ptr<Reconstruction> row =
            config.make(RowContext{space, &to_xyz, &protocol, &sets});
        for (std::size_t k = 0; k < sets.size(); ++k) {
          PatchSetResult r;
          r.set = validation_sets()[k];
          for (std::size_t i = 0; i < sets[k].size(); ++i)
            r.patches.push_back(
                run_patch(*row, protocol, to_xyz, from_xyz, k, i, sets[k][i], d65, lights));
          r.summary = summarise(r.patches, lights.size());
          c.sets.push_back(std::move(r));
        }
        if (!config.model.empty()) {
          const Spectralizer emission(model_settings(config.model, config.filter, Mode::emission));
          for (const char* light : {"A", "D50", "FL2"})
            c.lights.push_back(run_light(emission, to_xyz, from_xyz, light, checker));
        }
      } catch (const Error& e) {
        c.available = false;
        c.error = e.what();
        c.sets.clear();
        c.lights.clear();
      }
      c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      results.configs.push_back(std::move(c));
    }
  return results;
}

}  // namespace spectralize::figures
