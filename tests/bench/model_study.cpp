// The models on random colours (make bench): for each model and mode, 10,000 colours uniform in
// each unit RGB cube of Linear sRGB, Linear Rec.2020 and ACEScg (D65-adapted by Bradford),
// through the Spectralizer (gamut mapping included): how many were mapped, how often the model's
// fallback ran (natural: also its non-continuous safety net), the worst relative XYZ error by
// the library's weights, bound violations, and the solve time (median, p99, max) on one thread.
// Usage: model_study [COLOURS_PER_SPACE] [MODEL...]

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/spectralizer.h"

using namespace spectralize;

namespace {

using Mat = std::array<std::array<double, 3>, 3>;

Mat mul(const Mat& a, const Mat& b) {
  Mat m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) m[i][j] += a[i][k] * b[k][j];
  return m;
}

Mat inverse(const Mat& m) {
  const double d = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                   m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  Mat r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, e = (i + 2) % 3;
      r[i][j] = (m[a][c] * m[b][e] - m[a][e] * m[b][c]) / d;
    }
  return r;
}

// RGB -> XYZ of primaries xy and white xy (columns scaled so that RGB 1,1,1 is the white).
Mat rgb_to_xyz(std::array<double, 8> p) {
  Mat m{};
  for (int c = 0; c < 3; ++c) {
    const double x = p[2 * c], y = p[2 * c + 1];
    m[0][c] = x / y, m[1][c] = 1, m[2][c] = (1 - x - y) / y;
  }
  const double w[3] = {p[6] / p[7], 1, (1 - p[6] - p[7]) / p[7]};
  const Mat inv = inverse(m);
  for (int c = 0; c < 3; ++c) {
    const double s = inv[c][0] * w[0] + inv[c][1] * w[1] + inv[c][2] * w[2];
    for (int r = 0; r < 3; ++r) m[r][c] *= s;
  }
  return m;
}

// Bradford adaptation from white a to white b (XYZ with Y = 1).
Mat bradford(const double a[3], const double b[3]) {
  const Mat k = {{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  double la[3], lb[3];
  for (int i = 0; i < 3; ++i) {
    la[i] = k[i][0] * a[0] + k[i][1] * a[1] + k[i][2] * a[2];
    lb[i] = k[i][0] * b[0] + k[i][1] * b[1] + k[i][2] * b[2];
  }
  const Mat d = {{{lb[0] / la[0], 0, 0}, {0, lb[1] / la[1], 0}, {0, 0, lb[2] / la[2]}}};
  return mul(inverse(k), mul(d, k));
}

struct Space {
  const char* name;
  Mat to_xyz;
};

std::vector<Space> spaces() {
  const Mat ap1 = rgb_to_xyz({0.713, 0.293, 0.165, 0.830, 0.128, 0.044, 0.32168, 0.33767});
  const double aces_w[3] = {0.32168 / 0.33767, 1, (1 - 0.32168 - 0.33767) / 0.33767};
  const double d65_w[3] = {0.3127 / 0.3290, 1, (1 - 0.3127 - 0.3290) / 0.3290};
  return {{"sRGB", rgb_to_xyz({0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290})},
          {"Rec.2020", rgb_to_xyz({0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290})},
          {"ACEScg", mul(bradford(aces_w, d65_w), ap1)}};
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  const int per_space = argc > 1 ? std::atoi(argv[1]) : 10000;
  std::vector<std::string> models;
  for (int i = 2; i < argc; ++i) models.push_back(argv[i]);
  if (models.empty()) models = {"paper", "smooth", "natural"};
  std::printf(
      "model    mode         colours  mapped  fallback   safety net  max rel. err  bound "
      "viol.  us p50 / p99 / max\n");
  for (const std::string& model : models)
    for (Mode mode : {Mode::reflectance, Mode::emission}) {
      SpectralizerSettings s;
      s.model = model;
      s.mode = mode;
      const Spectralizer sp(s);
      std::mt19937 rng(2026);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      std::size_t n = 0, mapped = 0, fallback = 0, net = 0, violations = 0;
      double worst = 0;
      std::vector<double> us;
      for (const Space& space : spaces())
        for (int i = 0; i < per_space; ++i) {
          const double r = u(rng), g = u(rng), b = u(rng);
          const Mat& m = space.to_xyz;
          const Xyz xyz{m[0][0] * r + m[0][1] * g + m[0][2] * b,
                        m[1][0] * r + m[1][1] * g + m[1][2] * b,
                        m[2][0] * r + m[2][1] * g + m[2][2] * b};
          const auto t0 = std::chrono::steady_clock::now();
          const SpectrumResult res = sp.spectralize(xyz);
          us.push_back(
              std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0)
                  .count());
          ++n;
          mapped += out_of_gamut(res.status);
          fallback += res.fallback;
          net += res.detail("safety_net") != 0;
          worst = std::max(worst, res.relative_error);
          for (double v : res.values) violations += v < 0 || (mode == Mode::reflectance && v > 1);
        }
      std::printf("%-8s %-11s %8zu %7zu %6zu (%4.1f%%) %6zu %13.1e %11zu  %.1f / %.1f / %.0f\n",
                  model.c_str(), std::string(to_string(mode)).c_str(), n, mapped, fallback,
                  100.0 * static_cast<double>(fallback) / static_cast<double>(n), net, worst,
                  violations, quantile(us, 0.5), quantile(us, 0.99), quantile(us, 1.0));
    }
  return 0;
}
