// The Jakob & Hanika baseline's accuracy and build time (make bench): builds the sRGB table
// (default 64^3, 2 threads), then measures Delta E 1976 of random sRGB colours (uniform in the
// encoded cube, decoded) fitted directly and fetched through the table, the colours integrated
// by the project's reference weights (docs/DESIGN.md §3).
// Usage: sigmoid_study [resolution=64] [colours=20000] [threads=2] [max_coefficient=200|inf]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "baseline/sigmoid_spectrum.h"
#include "bench_colours.h"
#include "core/colorimetry/colour_difference.h"

using namespace spectralize;
using namespace spectralize::baseline;

namespace {

double delta_e76(const Xyz& a, const Xyz& b, const Xyz& white) {
  const Lab p = to_lab(a, white), q = to_lab(b, white);
  return std::sqrt((p.L - q.L) * (p.L - q.L) + (p.a - q.a) * (p.a - q.a) +
                   (p.b - q.b) * (p.b - q.b));
}

void summarise(const char* what, std::vector<double> de) {
  std::sort(de.begin(), de.end());
  double sum = 0;
  for (double d : de) sum += d;
  std::printf("%-22s max %.3f  p99 %.3f  mean %.4f  (dE76, %zu colours)\n", what, de.back(),
              de[de.size() * 99 / 100], sum / de.size(), de.size());
}

}  // namespace

int main(int argc, char** argv) {
  const int res = argc > 1 ? std::atoi(argv[1]) : 64;
  const int count = argc > 2 ? std::atoi(argv[2]) : 20000;
  const int threads = argc > 3 ? std::atoi(argv[3]) : 2;
  SigmoidFitterSettings settings;
  if (argc > 4) settings.max_coefficient = std::atof(argv[4]);
  const SigmoidFitter fitter(bench::kRec709ToXyz, settings);

  const auto t0 = std::chrono::steady_clock::now();
  const SigmoidTable table(fitter, res, threads);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "sRGB table %d^3 x 3 blocks (%d fits), %d threads, coefficient bound %g: %.2f s; "
      "worst node fit %.3f dE76\n",
      res, 3 * res * res * res, threads, settings.max_coefficient, build_s,
      table.max_node_delta_e());

  std::mt19937 rng(2019);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> direct, fetched;
  double fit_s = 0;
  for (int n = 0; n < count; ++n) {
    const std::array<double, 3> rgb = {bench::srgb_decode(u(rng)), bench::srgb_decode(u(rng)),
                                       bench::srgb_decode(u(rng))};
    const Xyz target = fitter.target_of(rgb);
    const auto t1 = std::chrono::steady_clock::now();
    const SigmoidFit f = fitter.fit(rgb);
    fit_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    direct.push_back(delta_e76(fitter.xyz_of(f.polynomial), target, fitter.reference_white()));
    const float r = float(rgb[0]), g = float(rgb[1]), b = float(rgb[2]);
    const SigmoidPolynomial p = table(r, g, b);
    const BasicSigmoidPolynomial<double> pd{p.c0, p.c1, p.c2};
    // The table's target is the float colour it was asked for.
    fetched.push_back(
        delta_e76(fitter.xyz_of(pd), fitter.target_of({r, g, b}), fitter.reference_white()));
  }
  summarise("direct fit", direct);
  summarise("through the table", fetched);
  std::printf("direct fit from the flat start: %.2f us per colour\n", 1e6 * fit_s / count);
  return 0;
}
