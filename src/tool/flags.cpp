#include "tool/flags.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <vector>

namespace spectralize::tool {

SpectralizerSettings spectral_settings(const Options& opt) {
  SpectralizerSettings s;
  s.grid = flag_value("--wavelengths", [&] { return WavelengthGrid::parse(opt.wavelengths); });
  s.observer = flag_value("--observer", [&] { return Observer::get(opt.observer).name; });
  s.illuminant = flag_value("--illuminant", [&] { return Illuminant::get(opt.illuminant).name; });
  if (!opt.filter.empty())
    s.filter = flag_value("--filter", [&] { return EdgeFilter::parse(opt.filter); });
  s.model = flag_value("--model", [&] { return parse_model(opt.model); });
  s.emission_basis =
      flag_value("--emission-basis", [&] { return parse_emission_basis(opt.emission_basis); });
  return s;
}

ColourInputs colour_inputs(const Options& opt) {
  SpectralizerSettings settings = spectral_settings(opt);
  settings.mode =
      flag_value("--mode", [&] { return parse_mode(opt.mode.empty() ? "emission" : opt.mode); });
  std::vector<Rgb> colours;
  for (const auto& text : opt.colors) colours.push_back(parse_rgb(text));
  ColourSpaces spaces = load_config(opt);
  const std::string space =
      opt.colorspace.empty() ? std::string(kDefaultColourSpace) : opt.colorspace;
  ColourTransform to_xyz = flag_value("--colorspace", [&] { return spaces.to_xyz(space); });
  return {std::move(settings), std::move(colours), std::move(spaces), std::move(to_xyz)};
}

SpectrumResult spectralize_colour(const Spectralizer& spectralizer, const ColourTransform& to_xyz,
                                  const Rgb& c, int& status) {
  SpectrumResult r = spectralizer.spectralize(to_xyz(c.r, c.g, c.b));
  if (r.status == Status::out_of_gamut)
    fmt::print(stderr,
               "spectralize WARNING: colour {} ({}) is out of gamut: {} (moved {:.6f} in xy)\n",
               c.text, to_xyz.source(), r.message, r.gamut_distance);
  if (r.status == Status::invalid) {
    fmt::print(stderr, "spectralize ERROR: colour {} ({}): {}\n", c.text, to_xyz.source(),
               r.message);
    status = kExitFailure;
  }
  return r;
}

// Parses "R,G,B" into three finite numbers.
Rgb parse_rgb(const std::string& text) {
  std::vector<double> v;
  std::size_t pos = 0;
  while (true) {
    std::size_t comma = text.find(',', pos);
    std::string part =
        text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    // Allow surrounding spaces ("0.2, 0.5, 0.1" quoted as one argument).
    std::size_t b = part.find_first_not_of(' '), e = part.find_last_not_of(' ');
    part = b == std::string::npos ? "" : part.substr(b, e - b + 1);
    const char* first = part.data() + (part.size() > 0 && part[0] == '+' ? 1 : 0);
    double x = 0;
    auto r = std::from_chars(first, part.data() + part.size(), x);
    if (part.empty() || r.ec != std::errc() || r.ptr != part.data() + part.size())
      throw UsageError{fmt::format("--color '{}': '{}' is not a number", text, part)};
    if (!std::isfinite(x))
      throw UsageError{
          fmt::format("--color '{}': components must be finite, got '{}'", text, part)};
    v.push_back(x);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (v.size() != 3)
    throw UsageError{
        fmt::format("--color '{}': expected 3 components R,G,B, got {}", text, v.size())};
  return {v[0], v[1], v[2], text};
}

ColourSpaces load_config(const Options& opt) {
  if (opt.config.empty()) return ColourSpaces::load();
  return flag_value("--config", [&] { return ColourSpaces::load(opt.config); });
}

int parse_int_flag(const char* flag, const std::string& text, int min, int max) {
  int v = 0;
  auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size())
    throw UsageError{fmt::format("{} '{}': not a whole number", flag, text)};
  if (v < min || v > max)
    throw UsageError{fmt::format("{} '{}': must be between {} and {}", flag, text, min, max)};
  return v;
}

}  // namespace spectralize::tool
