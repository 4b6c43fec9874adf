#pragma once
// The tests' oracle of a render-time table's exactness (the unit tests and the table fuzzer):
// the colour of a spectrum's samples under the table's own band weights, against the target
// colour of the RGB asked under the table's matrix.

#include <spectralize/rt.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace spz_test {

/// The largest difference between the two colours, relative to the asked one's largest
/// component (absolute for black). Cost: O(bands).
inline double relative_error(const spz::TableView& v, const std::vector<float>& x,
                             const float c[3]) {
  const double* m = v.header().rgb_to_target;
  const double* w =
      reinterpret_cast<const double*>(reinterpret_cast<const char*>(&v.header()) +
                                      v.header().sections[SPZ_SECTION_BAND_WEIGHTS].offset);
  double got[3] = {0, 0, 0}, scale = 0, err = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    for (int a = 0; a < 3; ++a) got[a] += static_cast<double>(x[k]) * w[3 * k + a];
  for (int a = 0; a < 3; ++a) {
    const double want = m[3 * a] * c[0] + m[3 * a + 1] * c[1] + m[3 * a + 2] * c[2];
    scale = std::max(scale, std::abs(want));
    err = std::max(err, std::abs(got[a] - want));
  }
  return scale > 0 ? err / scale : err;
}

}  // namespace spz_test
