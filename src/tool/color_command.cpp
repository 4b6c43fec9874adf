// spectralize --color: one or more colours to spectra, printed as CSV or JSON (to stdout or to
// the file of -o).

#include <fmt/core.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "imagefile/safe_output.h"
#include "pipeline/image_report.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"
#include "text/json_text.h"
#include "tool/colour_values.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

using Json = nlohmann::ordered_json;

Json xyz_json(const Xyz& v) {
  return Json::array({v.X, v.Y, v.Z});
}

Json result_json(const Rgb& rgb, const ColourSpaceFacts& space, const Options& opt,
                 const Spectralizer& sp, const SpectrumResult& r) {
  Json j;
  j["input_rgb"] = Json::array({rgb.r, rgb.g, rgb.b});
  j["colorspace"] = space.name;
  j.update(identity_record(SpaceIdentity::of(space)));
  // The settings that mattered, from the schema (mode resolved).
  Settings s = opt.settings;
  s.spectral = sp.settings();
  for (const auto& [key, value] : describe_settings(s, kColor))
    if (key != "colorspace" && key != "print_format") j[key] = value;
  j["status"] = std::string(to_string(r.status));
  if (!r.message.empty()) j["message"] = r.message;
  j["input_xyz"] = xyz_json(r.input);
  j["target_xyz"] = xyz_json(r.target);
  j["xyz"] = xyz_json(r.xyz);
  j["relative_error"] = r.relative_error;
  // The model's own details (the paper model: admissible, dropped, bounded, edge_capped).
  for (const ModelDetail& d : r.details) {
    if (d.boolean)
      j[d.name] = d.value != 0;
    else if (d.value == std::floor(d.value) && std::abs(d.value) < 9e15)
      j[d.name] = static_cast<long long>(d.value);  // counts print as integers
    else
      j[d.name] = d.value;
  }
  j["fallback"] = r.fallback;
  j["gamut_distance"] = r.gamut_distance;
  Json wl = Json::array(), values = Json::array();
  for (std::size_t i = 0; i < sp.settings().grid.size(); ++i) {
    wl.push_back(sp.settings().grid[i]);
    values.push_back(r.values[i]);
  }
  j["wavelengths_nm"] = std::move(wl);
  j["values"] = std::move(values);
  return j;
}

}  // namespace

int run_color(const Options& opt) {
  // JSON by --format, or by the extension of -o.
  const std::string ext = std::filesystem::path(opt.output).extension().string();
  const bool json = opt.given.count("--format") ? opt.settings.json : ext == ".json";
  const ColourInputs in = colour_inputs(opt);
  const auto& [settings, colours, spaces, to_xyz, frame] = in;
  // The destination is checked before any work (a file, or a stream such as /dev/stdout).
  std::unique_ptr<AtomicOutput> file;
  if (!opt.output.empty())
    file =
        std::make_unique<AtomicOutput>(opt.output, WriteRules::named("the output (-o)").streams());

  Spectralizer spectralizer(settings);
  // The exact table, as images and renderers' table files give spectra (--method exact: solved).
  std::unique_ptr<SpectralTable> table;
  if (opt.settings.method == SpectralTable::Method::table)
    table = std::make_unique<SpectralTable>(spectralizer, SpectralTable::Method::table, frame);
  std::vector<SpectrumResult> results;
  int status = kExitOk;
  for (const Rgb& c : colours)
    results.push_back(spectralize_colour(spectralizer, table.get(), to_xyz, c, status));

  std::string text;
  const auto& grid = settings.grid;
  if (json) {
    Json out = Json::array();
    for (std::size_t i = 0; i < results.size(); ++i)
      out.push_back(
          result_json(colours[i], spaces->facts(to_xyz.source()), opt, spectralizer, results[i]));
    text = dump_json(results.size() == 1 ? out[0] : out, 2) + "\n";
  } else {
    text = "wavelength_nm";
    for (std::size_t c = 0; c < results.size(); ++c)
      text += results.size() == 1 ? ",value" : fmt::format(",value_{}", c + 1);
    text += "\n";
    for (std::size_t i = 0; i < grid.size(); ++i) {
      text += fmt::format("{}", grid[i]);
      for (const auto& r : results) text += fmt::format(",{}", r.values[i]);
      text += "\n";
    }
  }
  if (file) {
    file->write(text);
    file->commit();
  } else {
    fmt::print("{}", text);
  }
  return status;
}

}  // namespace spectralize::tool
