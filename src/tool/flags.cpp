#include "tool/flags.h"

#include <fmt/core.h>

#include <charconv>

namespace spectralize::tool {

SpectralizerSettings spectral_settings(const Options& opt) {
  SpectralizerSettings s;
  s.grid = flag_value("--wavelengths", [&] { return WavelengthGrid::parse(opt.wavelengths); });
  s.observer = flag_value("--observer", [&] { return Observer::get(opt.observer).name; });
  s.illuminant = flag_value("--illuminant", [&] { return Illuminant::get(opt.illuminant).name; });
  if (!opt.filter.empty())
    s.filter = flag_value("--filter", [&] { return EdgeFilter::parse(opt.filter); });
  return s;
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
