#include "tool/colour_values.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "classify/input_interpretation.h"
#include "core/decimal_number.h"
#include "pipeline/job_plan.h"
#include "pipeline/render_table.h"
#include "text/strings.h"

namespace spectralize::tool {

ColourInputs colour_inputs(const Options& opt) {
  std::vector<Rgb> colours;
  for (const auto& text : opt.colors) colours.push_back(parse_rgb(text));
  const JobPlan plan = usage_checked("", [&] {
    return plan_colours(opt.settings, ColourSubject::colours, OptionNames{"--", "-o"});
  });
  for (const std::string& w : plan.warnings) fmt::print(stderr, "spectralize WARNING: {}\n", w);
  const ColourSpaces& spaces = plan.colour_spaces();
  ColourTransform to_xyz =
      usage_checked("--colorspace", [&] { return spaces.to_xyz(plan.colorspace.name()); });
  const Mat3 frame = table_frame(spaces, to_xyz.source());
  return {plan.settings.spectral, std::move(colours), plan.spaces, std::move(to_xyz), frame};
}

SpectrumResult spectralize_colour(const Spectralizer& spectralizer, SpectralTable* table,
                                  const ColourTransform& to_xyz, const Rgb& c, int& status) {
  const Xyz xyz = to_xyz(c.r, c.g, c.b);
  SpectrumResult r;
  if (table) {
    // The table's spectrum (float), with what the Spectralizer says about the colour.
    r = spectralizer.classify(xyz);
    std::vector<float> v(spectralizer.settings().grid.size());
    PixelResult pixel;
    table->spectra(&xyz, 1, v.data(), &pixel);
    // Printed as the float it is (shortest text that reads back as that float).
    for (std::size_t i = 0; i < v.size(); ++i)
      r.values[i] = std::strtod(fmt::format("{}", v[i]).c_str(), nullptr);
    if (r.status == Outcome::exact || out_of_gamut(r.status)) r.target = pixel.target;
    r.xyz = spectralizer.weights().integrate(r.values);
    r.relative_error = r.target.max_abs() > 0 ? relative_error(r.xyz, r.target) : 0.0;
  } else {
    r = spectralizer.spectralize(xyz);
  }
  if (r.status == Outcome::negative) {
    // As for a pixel: out of gamut, mapped to black with a warning, not a failure.
    fmt::print(stderr,
               "spectralize WARNING: colour {} ({}) is out of gamut: it has negative luminance "
               "(Y < 0), which no light or surface has; mapped to black (zero spectrum)\n",
               c.text, to_xyz.source());
  } else if (out_of_gamut(r.status)) {
    std::string hint;
    // A reflectance far above white is usually 0..255 or 0..65535 data given as 0..1.
    if (spectralizer.settings().mode == Mode::reflectance &&
        spectralizer.target_of(xyz).Y > spectralizer.reference_white().Y * (1 + 1e-6))
      hint = std::max({c.r, c.g, c.b}) > 2
                 ? " (brighter than white: reflectances are 0..1; did you mean 0-1 values?)"
                 : " (brighter than white)";
    fmt::print(stderr,
               "spectralize WARNING: colour {} ({}) is out of gamut{}: {} (moved {:.6f} in xy)\n",
               c.text, to_xyz.source(), hint, r.message, r.gamut_distance);
  }
  if (r.status == Outcome::invalid) {
    fmt::print(stderr, "spectralize ERROR: colour {} ({}): {}\n", c.text, to_xyz.source(),
               r.message);
    status = kExitFailure;
  }
  return r;
}

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
    try {
      v.push_back(decimal_number(part));
    } catch (const Error& e) {
      throw UsageError{fmt::format("--color '{}': {}", clip(text), e.what())};
    }
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (v.size() != 3)
    throw UsageError{fmt::format(
        "--color '{}': expected 3 components R,G,B separated by commas, got {}{}", clip(text),
        v.size(), v.size() == 1 ? " (write --color 1,0.5,0.2, not --color 1 0.5 0.2)" : "")};
  return {v[0], v[1], v[2], text};
}

}  // namespace spectralize::tool
