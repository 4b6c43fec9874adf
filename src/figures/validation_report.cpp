#include "figures/validation_report.h"

#include <fmt/core.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <system_error>

#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"

namespace fs = std::filesystem;

namespace spectralize::figures {

namespace {

nlohmann::json spread_json(const Spread& s) {
  return {{"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

// {"A": f(0), "FL11": f(1), ...} over validation_lights().
template <typename F>
nlohmann::json per_light(F&& f) {
  nlohmann::json j = nlohmann::json::object();
  const std::vector<std::string> lights = validation_lights();
  for (std::size_t k = 0; k < lights.size(); ++k) j[lights[k]] = f(k);
  return j;
}

std::string spread_md(const Spread& s) {
  return fmt::format("{:.3g} / {:.3g} / {:.3g}", s.median, s.p95, s.max);
}

// "Linear Rec.709 (sRGB)" -> "sRGB" in tables.
std::string short_space(const std::string& space) {
  return space == "Linear Rec.709 (sRGB)" ? "sRGB"
         : space == "Linear Rec.2020"     ? "Rec.2020"
                                          : space;
}

constexpr const char* kDefinitions[][2] = {
    {"delta_e_d65",
     "CIEDE2000 under D65 between the reconstructed spectrum and the input colour "
     "(the round trip; the spectralizer is exact, so ~0)"},
    {"delta_e_d65_measured",
     "CIEDE2000 under D65 between reconstruction and measurement "
     "(differs from delta_e_d65 only for patches clipped to the space)"},
    {"delta_e",
     "per light (CIE A, FL11, FL2, LED-B3, HP1, D50): CIEDE2000 under that light between "
     "reconstruction and measurement (metamerism), CIELAB relative to the white (rho == 1) "
     "under the light"},
    {"rmse", "RMS difference of reconstruction and measurement over the grid samples"},
    {"roughness", "RMS of the second differences x[i-1] - 2 x[i] + x[i+1] over the grid (5 nm)"},
    {"edge_ratio",
     "the largest sample within 20 nm of either end of the grid over the mean of "
     "the samples in 400..700 nm (the guide's edge-peak figure)"},
    {"relative_xyz_error",
     "max |XYZ - target| / max |target|, XYZ by the reference integration "
     "(1 nm CIE tables, piecewise-linear spectrum)"},
    {"exact", "the row reproduces every patch's D65 colour (reference lines may not)"},
    {"lights",
     "CIE A, D50, FL2 sampled on the grid, normalised to Y = 1, given as RGB in the "
     "space, spectralized as emission and normalised to Y = 1; checker_delta_e: the 24 "
     "measured patches lit by the reconstructed vs the real light, each relative to its "
     "white"},
};

void write_file(const fs::path& path, const std::string& text) {
  AtomicOutput file(path.string(), {});
  file.write(text);
  file.commit();
}

}  // namespace

std::string validation_json(const Validation& results) {
  const SpectralizerSettings defaults;
  nlohmann::json doc;
  doc["data"] = nlohmann::json::array();
  for (const PatchSet& set : validation_sets()) doc["data"].push_back(set.file);
  doc["grid"] = defaults.grid.to_string();
  doc["observer"] = defaults.observer;
  doc["reference_illuminant"] = defaults.illuminant;
  for (const auto& d : kDefinitions) doc["definitions"][d[0]] = d[1];
  doc["lights"] = validation_lights();
  doc["configurations"] = nlohmann::json::array();
  for (const ConfigResult& c : results.configs) {
    nlohmann::json j;
    j["name"] = c.config.name;
    j["model"] = c.config.model;
    j["filter"] = !c.config.model.empty() && find_model(c.config.model).uses("filter")
                      ? c.config.filter.to_string()
                      : "";
    j["exact"] = c.config.exact;
    j["space"] = c.space;
    j["available"] = c.available;
    if (!c.available) j["error"] = c.error;
    j["seconds"] = c.seconds;
    j["sets"] = nlohmann::json::array();
    for (const PatchSetResult& r : c.sets) {
      const ValidationSummary& s = r.summary;
      nlohmann::json set{{"name", r.set.name}, {"data", r.set.file}};
      set["summary"] = {
          {"delta_e_d65", spread_json(s.delta_e_d65)},
          {"delta_e", per_light([&](std::size_t k) { return spread_json(s.delta_e[k]); })},
          {"mean_rmse", s.mean_rmse},
          {"mean_roughness", s.mean_roughness},
          {"mean_roughness_measured", s.mean_roughness_measured},
          {"max_relative_xyz_error", s.max_relative_xyz_error},
          {"max_edge_ratio", s.max_edge_ratio},
          {"max_edge_ratio_measured", s.max_edge_ratio_measured},
          {"rho_min", s.rho_min},
          {"rho_max", s.rho_max},
          {"clipped_patches", s.clipped}};
      set["patches"] = nlohmann::json::array();
      for (const PatchResult& p : r.patches)
        set["patches"].push_back(
            {{"name", p.name},
             {"rgb", p.rgb},
             {"clipped", p.clipped},
             {"status", p.status},
             {"delta_e_d65", p.delta_e_d65},
             {"delta_e_d65_measured", p.delta_e_d65_measured},
             {"delta_e", per_light([&](std::size_t k) { return p.delta_e[k]; })},
             {"rmse", p.rmse},
             {"roughness", p.roughness},
             {"roughness_measured", p.roughness_measured},
             {"edge_ratio", p.edge_ratio},
             {"edge_ratio_measured", p.edge_ratio_measured},
             {"relative_xyz_error", p.relative_xyz_error},
             {"rho_min", p.rho_min},
             {"rho_max", p.rho_max}});
      j["sets"].push_back(std::move(set));
    }
    j["lights"] = nlohmann::json::array();
    for (const LightResult& l : c.lights)
      j["lights"].push_back({{"name", l.name},
                             {"rgb", l.rgb},
                             {"in_gamut", l.in_gamut},
                             {"status", l.status},
                             {"delta_e_light", l.delta_e_light},
                             {"rmse", l.rmse},
                             {"roughness", l.roughness},
                             {"roughness_real", l.roughness_real},
                             {"edge_ratio", l.edge_ratio},
                             {"relative_xyz_error", l.relative_xyz_error},
                             {"checker_delta_e_median", l.checker_delta_e_median},
                             {"checker_delta_e_max", l.checker_delta_e_max}});
    doc["configurations"].push_back(std::move(j));
  }
  doc["rgb_renderer"] = nlohmann::json::array();
  for (const RgbBaseline& b : results.baselines) {
    nlohmann::json j{
        {"space", b.space},
        {"set", b.set},
        {"delta_e", per_light([&](std::size_t k) { return spread_json(b.spreads[k]); })},
        {"patches", nlohmann::json::array()}};
    for (std::size_t i = 0; i < b.patches.size(); ++i)
      j["patches"].push_back({{"name", b.patches[i]}, {"delta_e", per_light([&](std::size_t k) {
                                                         return b.delta_e[k][i];
                                                       })}});
    doc["rgb_renderer"].push_back(std::move(j));
  }
  return doc.dump(1) + "\n";
}

std::string summary_table(const Validation& results) {
  const std::vector<std::string> lights = validation_lights();
  std::string md = "| set | configuration | space | ΔE00 D65 (round trip) med / p95 / max |";
  for (const std::string& l : lights) md += " ΔE00 " + l + " med / p95 / max |";
  md += " mean RMSE | mean roughness | max edge ratio | max rel. XYZ error | ρ min … max |\n|";
  for (std::size_t k = 0; k < lights.size() + 9; ++k) md += "---|";
  md += "\n";
  const std::string blank_lights = [&] {
    std::string b;
    for (std::size_t k = 0; k < lights.size(); ++k) b += " |";
    return b;
  }();
  for (const PatchSet& set : validation_sets()) {
    for (const ConfigResult& c : results.configs) {
      if (!c.available) {
        md += fmt::format("| {} | {} | {} | unavailable: {} |{} | | | | |\n", set.name,
                          c.config.name, short_space(c.space), c.error, blank_lights);
        continue;
      }
      for (const PatchSetResult& r : c.sets) {
        if (r.set.name != set.name) continue;
        const ValidationSummary& s = r.summary;
        md += fmt::format("| {} | {} | {}{} | {} |", set.name, c.config.name, short_space(c.space),
                          s.clipped ? fmt::format(" ({} clipped)", s.clipped) : "",
                          spread_md(s.delta_e_d65));
        for (const Spread& d : s.delta_e) md += fmt::format(" {} |", spread_md(d));
        md += fmt::format(" {:.4f} | {:.4f} | {:.2f} | {:.1e} | {:.3f} … {:.3f} |\n", s.mean_rmse,
                          s.mean_roughness, s.max_edge_ratio, s.max_relative_xyz_error, s.rho_min,
                          s.rho_max);
      }
    }
    // What the spectra are for: an RGB renderer gets the other lights this wrong.
    for (const RgbBaseline& b : results.baselines)
      if (b.set == set.name) {
        md += fmt::format("| {} | RGB renderer (no spectra; baseline) | {} | 0 by construction |",
                          set.name, short_space(b.space));
        for (const Spread& d : b.spreads) md += fmt::format(" {} |", spread_md(d));
        md += " | | | | |\n";
      }
  }
  return md;
}

// The measured spectra's own roughness and edge ratio, per set (from the first configuration).
std::string measured_note(const std::vector<ConfigResult>& results) {
  std::string note;
  if (results.empty() || !results[0].available) return note;
  for (const PatchSetResult& r : results[0].sets)
    note += fmt::format("{}{} measured: mean roughness {:.4f}, max edge ratio {:.2f}",
                        note.empty() ? "" : "; ", r.set.name, r.summary.mean_roughness_measured,
                        r.summary.max_edge_ratio_measured);
  return note;
}

std::string lights_table(const std::vector<ConfigResult>& results) {
  std::string md =
      "| configuration | space | light | RGB | spectral RMSE | roughness (real) | edge ratio | "
      "ΔE00 of the light | ColorChecker under it: ΔE00 med / max |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (const ConfigResult& c : results)
    for (const LightResult& l : c.lights)  // models only: reference rows make no lights
      md += fmt::format(
          "| {} | {} | {} | {:.3f}, {:.3f}, {:.3f}{} | {:.4f} | {:.4f} ({:.4f}) | "
          "{:.2f} | {:.1e} | {:.3g} / {:.3g} |\n",
          c.config.name, short_space(c.space), l.name, l.rgb[0], l.rgb[1], l.rgb[2],
          l.in_gamut ? "" : " (out of gamut)", l.rmse, l.roughness, l.roughness_real, l.edge_ratio,
          l.delta_e_light, l.checker_delta_e_median, l.checker_delta_e_max);
  return md;
}

std::string validation_markdown(const Validation& v) {
  const std::vector<ConfigResult>& results = v.configs;
  const SpectralizerSettings defaults;
  std::string md = "# Validation on measured reflectances\n\n";
  md += fmt::format(
      "Made by `make validate` (`spectralize_figures validate`). The 24 ColorChecker "
      "reflectances measured by N. Ohta (`data/colorchecker_n_ohta_5nm.csv`) and the 190 AMPAS "
      "rawtoaces training patches (`data/ampas_rawtoaces_190_patches_5nm.csv`) are turned into "
      "colours under D65 (relative to the reflected white, the paper's eq. 6) in each space — "
      "clipped to [0, 1] when outside it, as a texture would hold them —, reconstructed as "
      "reflectances by every row ({} nm, {}, reference illuminant {}: the registered models and "
      "reference lines that are not models) and compared with the measurement under D65 and six "
      "other lights (docs/MODEL_STUDY.md). Spectral figures are on the grid samples.\n\n",
      defaults.grid.to_string(), defaults.observer, defaults.illuminant);
  for (const auto& d : kDefinitions) md += fmt::format("- `{}`: {}\n", d[0], d[1]);
  md += "\n## Reflectances: summary\n\n" + summary_table(v);
  if (const std::string note = measured_note(results); !note.empty())
    md += "\nThe measured spectra, for comparison: " + note +
          " (red patches reflect most at the long end: for reflectances a high edge ratio is not "
          "by itself an artefact).\n";
  md += fmt::format(
      "\nThe RGB renderer rows show each patch under each light as its RGB times the light's RGB "
      "(the light's colour in the space, as a renderer without spectra does), against the "
      "measured spectrum under that light.\n");
  md += "\n## Lights: CIE illuminants given as RGB\n\n" + lights_table(results);
  for (const ConfigResult& c : results) {
    md += fmt::format("\n## {} — {}\n\n", c.config.name, c.space);
    if (!c.available) {
      md += "Unavailable: " + c.error + "\n";
      continue;
    }
    for (const PatchSetResult& r : c.sets) {
      md += fmt::format("\n### {}\n\n", r.set.name);
      md += "| patch | RGB | status | ΔE00 D65 | ΔE00 D65 vs measured |";
      for (const std::string& l : validation_lights()) md += " ΔE00 " + l + " |";
      md += " RMSE | roughness (measured) | edge ratio | rel. XYZ error | ρ min … max |\n|";
      for (std::size_t k = 0; k < validation_lights().size() + 10; ++k) md += "---|";
      md += "\n";
      for (const PatchResult& p : r.patches) {
        md += fmt::format("| {} | {:.4f}, {:.4f}, {:.4f}{} | {} | {:.1e} | {:.3g} |", p.name,
                          p.rgb[0], p.rgb[1], p.rgb[2], p.clipped ? " (clipped)" : "", p.status,
                          p.delta_e_d65, p.delta_e_d65_measured);
        for (double d : p.delta_e) md += fmt::format(" {:.3g} |", d);
        md += fmt::format(" {:.4f} | {:.4f} ({:.4f}) | {:.2f} | {:.1e} | {:.3f} … {:.3f} |\n",
                          p.rmse, p.roughness, p.roughness_measured, p.edge_ratio,
                          p.relative_xyz_error, p.rho_min, p.rho_max);
      }
    }
  }
  return md;
}

void run_validation(const std::string& outdir, std::ostream& out) {
  std::error_code ec;
  fs::create_directories(outdir, ec);
  if (ec) throw Error("cannot create the output folder '" + outdir + "': " + ec.message());
  const ColourSpaces spaces = ColourSpaces::load();
  const Validation v = validate(spaces);
  const std::vector<ConfigResult>& results = v.configs;
  write_file(fs::path(outdir) / "validation.json", validation_json(v));
  write_file(fs::path(outdir) / "validation.md", validation_markdown(v));
  fmt::print(out, "{}\n{}", summary_table(v), lights_table(results));
  if (const std::string note = measured_note(results); !note.empty()) fmt::print(out, "{}\n", note);
  for (const ConfigResult& c : results)
    if (!c.available)
      fmt::print(out, "validate: configuration '{}' unavailable: {}\n", c.config.name, c.error);
  fmt::print(out, "validate: wrote {}/validation.json and {}/validation.md\n", outdir, outdir);
}

}  // namespace spectralize::figures
