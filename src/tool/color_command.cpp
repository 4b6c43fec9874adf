// spectralize --color: one or more colours to spectra, printed as CSV or JSON.

#include <fmt/core.h>
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/spectralizer.h"
#include "io/colour_space.h"
#include "io/spectrum_plot.h"
#include "tool/flags.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

using Json = nlohmann::ordered_json;

Json xyz_json(const Xyz& v) {
  return Json::array({v.X, v.Y, v.Z});
}

Json result_json(const Rgb& rgb, const std::string& space, const Spectralizer& sp,
                 const SpectrumResult& r) {
  const auto& s = sp.settings();
  Json j;
  j["input_rgb"] = Json::array({rgb.r, rgb.g, rgb.b});
  j["colorspace"] = space;
  j["mode"] = std::string(to_string(s.mode));
  j["wavelengths"] = s.grid.to_string();
  j["observer"] = sp.observer().name;
  if (s.mode == Mode::reflectance) j["illuminant"] = sp.illuminant()->name;
  if (s.model == Model::paper) j["filter"] = s.filter.to_string();  // the paper model's only
  j["model"] = std::string(to_string(s.model));
  if (s.mode == Mode::emission) j["emission_basis"] = s.emission_basis;
  j["status"] = std::string(to_string(r.status));
  if (!r.message.empty()) j["message"] = r.message;
  j["input_xyz"] = xyz_json(r.input);
  j["target_xyz"] = xyz_json(r.target);
  j["xyz"] = xyz_json(r.xyz);
  j["relative_error"] = r.relative_error;
  j["admissible"] = r.admissible;
  j["dropped"] = r.dropped;
  j["bounded"] = r.bounded;
  j["edge_capped"] = r.edge_capped;
  j["gamut_distance"] = r.gamut_distance;
  Json wl = Json::array(), values = Json::array();
  for (std::size_t i = 0; i < s.grid.size(); ++i) {
    wl.push_back(s.grid[i]);
    values.push_back(r.values[i]);
  }
  j["wavelengths_nm"] = std::move(wl);
  j["values"] = std::move(values);
  return j;
}

}  // namespace

int run_color(const Options& opt) {
  // -o naming an image or an .svg: draw the spectra instead of printing them.
  if (!opt.output.empty() && is_plot_path(opt.output)) return run_plot_color(opt);
  // Validate every flag before any work, so a mistake is reported as such (exit 2).
  const std::string format = opt.format.empty() ? "csv" : opt.format;
  if (format != "csv" && format != "json")
    throw UsageError{fmt::format("--format '{}': valid formats for --color are csv, json", format)};
  const ColourInputs in = colour_inputs(opt);
  const auto& [settings, colours, spaces, to_xyz] = in;

  Spectralizer spectralizer(settings);
  std::vector<SpectrumResult> results;
  int status = kExitOk;
  for (const Rgb& c : colours)
    results.push_back(spectralize_colour(spectralizer, to_xyz, c, status));

  const auto& grid = settings.grid;
  if (format == "json") {
    Json out = Json::array();
    for (std::size_t i = 0; i < results.size(); ++i)
      out.push_back(result_json(colours[i], to_xyz.source(), spectralizer, results[i]));
    fmt::print("{}\n", (results.size() == 1 ? out[0] : out).dump(2));
  } else {
    std::string header = "wavelength_nm";
    for (std::size_t c = 0; c < results.size(); ++c)
      header += results.size() == 1 ? ",value" : fmt::format(",value_{}", c + 1);
    fmt::print("{}\n", header);
    for (std::size_t i = 0; i < grid.size(); ++i) {
      std::string row = fmt::format("{}", grid[i]);
      for (const auto& r : results) row += fmt::format(",{}", r.values[i]);
      fmt::print("{}\n", row);
    }
  }
  return status;
}

}  // namespace spectralize::tool
