// Spectralizes a colour with the installed core library and checks, by its own trapezoid
// integration of the installed CIE 1931 table (docs/DESIGN.md §3), that the spectrum
// reproduces the colour. Prints "ok <version> <relative error>"; exit 1 otherwise.
// Usage: consumer CIE1931_CSV
#include <spectralize/core/spectralizer.h>
#include <spectralize/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  // The 1 nm table: wavelength, xbar, ybar, zbar.
  std::ifstream csv(argv[1]);
  std::string line;
  std::getline(csv, line);
  std::vector<double> nm, cmf[3];
  while (std::getline(csv, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream in(line);
    double w, x, y, z;
    if (!(in >> w >> x >> y >> z)) continue;
    nm.push_back(w), cmf[0].push_back(x), cmf[1].push_back(y), cmf[2].push_back(z);
  }
  spectralize::SpectralizerSettings settings;  // 380:780:5, emission, the default model
  const spectralize::Spectralizer sp(settings);
  const spectralize::Xyz target{0.3, 0.4, 0.2};
  const spectralize::SpectrumResult r = sp.spectralize(target);
  // Piecewise-linear spectrum on the 1 nm table, trapezoid weights, K = sum tau * ybar.
  const auto& grid = settings.grid;
  double xyz[3] = {0, 0, 0}, k = 0;
  for (std::size_t i = 0; i < nm.size(); ++i) {
    const double tau = (i == 0 || i + 1 == nm.size()) ? 0.5 : 1.0;
    k += tau * cmf[1][i];
    double s = 0;
    const double t = (nm[i] - grid.start()) / grid.step();
    if (t >= 0 && t <= static_cast<double>(grid.size() - 1)) {
      const auto j = static_cast<std::size_t>(std::floor(t));
      const double f = t - static_cast<double>(j);
      s = j + 1 < grid.size() ? (1 - f) * r.values[j] + f * r.values[j + 1] : r.values[j];
    }
    for (int c = 0; c < 3; ++c) xyz[c] += tau * cmf[c][i] * s;
  }
  double err = 0;
  for (int c = 0; c < 3; ++c) err = std::max(err, std::abs(xyz[c] / k - target[c]) / 0.4);
  std::printf("%s %s %.3g\n", err <= 1e-9 ? "ok" : "FAILED", SPECTRALIZE_VERSION, err);
  return err <= 1e-9 ? 0 : 1;
}
