#include "path_tracer/image_difference.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/colorimetry/colour_difference.h"
#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

std::vector<double> delta_e_map(const std::vector<Xyz>& a, const std::vector<Xyz>& b,
                                const Xyz& white) {
  if (a.size() != b.size())
    throw Error("delta E map: images of " + std::to_string(a.size()) + " and " +
                std::to_string(b.size()) + " pixels");
  std::vector<double> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    out[i] = delta_e_2000(to_lab(a[i], white), to_lab(b[i], white));
  return out;
}

DeltaEStats summarize(const std::vector<double>& delta_e, const std::vector<bool>& mask) {
  std::vector<double> v;
  for (std::size_t i = 0; i < delta_e.size(); ++i)
    if (mask.empty() || mask[i]) v.push_back(delta_e[i]);
  DeltaEStats s;
  s.pixels = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (const double d : v) sum += d;
  s.mean = sum / static_cast<double>(v.size());
  const std::size_t rank =
      static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(v.size())));
  s.p95 = v[std::max<std::size_t>(rank, 1) - 1];
  s.max = v.back();
  return s;
}

}  // namespace spectralize::path_tracer
