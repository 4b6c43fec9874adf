// Evaluates the spectrum of a colour from a table file with the installed header-only
// evaluator, and checks by its own trapezoid integration of the installed CIE 1931 and D65
// tables (docs/DESIGN.md §3) that the reflectance reproduces the colour under the table's
// conventions. Prints "ok <relative error>"; exit 1 otherwise.
// Usage: rt_consumer TABLE.spztab CIE1931_CSV D65_CSV
// The program's one unit, so it compiles the evaluator's definitions (rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

// A CSV of wavelength and columns, on the 1 nm table.
std::vector<std::vector<double>> read(const char* path) {
  std::ifstream csv(path);
  std::string line;
  std::getline(csv, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(csv, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream in(line);
    std::vector<double> row;
    for (double v; in >> v;) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) return 2;
  spz::Table table;
  std::string error;
  if (!table.load(argv[1], &error)) {
    std::printf("FAILED: %s\n", error.c_str());
    return 1;
  }
  const spz::TableView& t = table.view();
  const float rgb[3] = {0.2f, 0.5f, 0.1f};
  spz::Spectrum s;
  if (t.fetch(rgb, s) != SPZ_EXACT || !t.reflectance()) return 1;
  // The spectrum's XYZ under D65, normalised so that rho == 1 has Y = 1, against the table's
  // RGB -> XYZ white balanced to the reflected white (rho == 1) from D65's chromaticity.
  const auto cmf = read(argv[2]), d65 = read(argv[3]);
  double xyz[3] = {0, 0, 0}, white[3] = {0, 0, 0};
  for (std::size_t i = 0; i < cmf.size(); ++i) {
    const double nm = cmf[i][0], tau = (i == 0 || i + 1 == cmf.size()) ? 0.5 : 1.0;
    double e = 0;
    for (const auto& row : d65)
      if (row[0] == nm) e = row[1];
    const double v = spz::eval(s, static_cast<float>(nm));
    const bool inside =
        nm >= t.lambda_start() && nm <= t.lambda_start() + t.lambda_step() * (t.bands() - 1);
    for (int c = 0; c < 3; ++c) {
      xyz[c] += tau * cmf[i][1 + c] * e * v;
      white[c] += tau * cmf[i][1 + c] * e * (inside ? 1.0 : 0.0);
    }
  }
  const double* m = t.header().rgb_to_xyz;
  const double d65w[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};
  double err = 0;
  for (int c = 0; c < 3; ++c) {
    const double want = (m[3 * c] * rgb[0] + m[3 * c + 1] * rgb[1] + m[3 * c + 2] * rgb[2]) *
                        (white[c] / white[1]) / d65w[c];
    err = std::max(err, std::abs(xyz[c] / white[1] - want) / 0.5);
  }
  std::printf("%s %s %.3g\n", err <= 1e-5 ? "ok" : "FAILED", t.header().colorspace, err);
  return err <= 1e-5 ? 0 : 1;
}
