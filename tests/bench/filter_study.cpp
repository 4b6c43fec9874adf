// Measures the edge-peak filter's trade-off for choosing its default (the guide's "Edge filter"
// (docs/guide/conventions.md)): for each drop fraction, the worst edge peak (largest sample in
// 380-400 or 760-780 nm over the mean in 400-700 nm) and the roughness (RMS of second differences
// over the mean) of emission spectra of the paper's light and of random sRGB colours (fixed seed).
// Run: build/tests/bench/filter_study [colours=2000]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench_colours.h"
#include "spectralize/core/spectralizer.h"

using namespace spectralize;
using bench::rec709;
using bench::srgb_decode;

namespace {

struct Shape {
  double edge_ratio, roughness;
};

Shape shape(const WavelengthGrid& g, const std::vector<double>& v) {
  double mean = 0, edge = 0, rough = 0;
  int n = 0, m = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (g[i] >= 400 && g[i] <= 700) mean += v[i], ++n;
    if (g[i] <= 400 || g[i] >= 760) edge = std::max(edge, v[i]);
    if (i > 0 && i + 1 < v.size() && g[i] >= 400 && g[i] <= 700) {
      double d2 = v[i - 1] - 2 * v[i] + v[i + 1];
      rough += d2 * d2, ++m;
    }
  }
  mean /= n;
  return {edge / mean, std::sqrt(rough / m) / mean};
}

}  // namespace

int main(int argc, char** argv) {
  const int colours = argc > 1 ? std::atoi(argv[1]) : 2000;
  std::printf("%-8s %-14s %-16s %-16s %-18s %-14s\n", "drop", "light edge", "sRGB lin worst",
              "sRGB enc worst", "median roughness", "light rough.");
  for (double f : {0.0, 0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 0.98, -1.0}) {
    SpectralizerSettings s;
    s.filter = f < 0 ? EdgeFilter::automatic() : EdgeFilter::fraction(f);
    Spectralizer sp(s);
    Shape light = shape(s.grid, sp.spectralize(rec709(6000, 5000, 1000)).values);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    double worst_lin = 0, worst_enc = 0;
    int capped = 0;
    std::vector<double> rough;
    for (int i = 0; i < colours; ++i) {
      double r = u(rng), gg = u(rng), b = u(rng);
      Shape a = shape(s.grid, sp.spectralize(rec709(r, gg, b)).values);
      Shape e = shape(
          s.grid, sp.spectralize(rec709(srgb_decode(r), srgb_decode(gg), srgb_decode(b))).values);
      worst_lin = std::max(worst_lin, a.edge_ratio);
      worst_enc = std::max(worst_enc, e.edge_ratio);
      rough.push_back(a.roughness);
    }
    std::nth_element(rough.begin(), rough.begin() + rough.size() / 2, rough.end());
    std::string label = f < 0 ? std::string("auto") : std::to_string(f).substr(0, 4);
    std::printf("%-8s %-14.3f %-16.3f %-16.3f %-18.3f %-14.3f\n", label.c_str(), light.edge_ratio,
                worst_lin, worst_enc, rough[rough.size() / 2], light.roughness);
    if (f < 0)
      std::printf("auto: %d of %d colours needed the exact edge cap after the ladder\n", capped,
                  2 * colours);
  }
}
