// Chooses the smooth model's roughness measure by measurement: the 24 ColorChecker N Ohta
// reflectances, taken under D65, reconstructed by each model, then compared with the measured
// spectra under illuminants A and FL11 (CIEDE2000 median / 95th percentile / max), plus the
// spectral RMSE and the time per solve. Usage: smooth_study [grid], default 380:780:5.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "core/solvers/smooth_solver.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/spectralizer.h"

using namespace spectralize;

namespace {

// The value of a 5 nm table at the grid's wavelengths (linear; the grid lies inside 380..780).
std::vector<double> resample(const std::vector<double>& nm, const std::vector<double>& v,
                             const WavelengthGrid& grid) {
  std::vector<double> out(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double w = grid[i];
    std::size_t k = 0;
    while (k + 2 < nm.size() && nm[k + 1] < w) ++k;
    const double f = std::clamp((w - nm[k]) / (nm[k + 1] - nm[k]), 0.0, 1.0);
    out[i] = (1 - f) * v[k] + f * v[k + 1];
  }
  return out;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  const double f = pos - static_cast<double>(i);
  return i + 1 < v.size() ? (1 - f) * v[i] + f * v[i + 1] : v[i];
}

struct Method {
  std::string name;
  std::string model;
  double tau_nm;     // curvature length
  bool log = false;  // roughness of log(rho) instead of rho (study only)
};

// The log-space variant, for comparison only: least roughness of y = log(rho) subject to
// W exp(y) = target and y <= 0, by sequential quadratic programming: each step solves the
// linearised constraints W diag(rho) (y' - y) = target - W rho with the same QP solver, in
// z = -y' >= 0. Starts from the linear smooth spectrum (floored at 1e-4); full steps unless the
// constraint error grows tenfold (then halved). Converges here on all 24 patches; on random
// saturated colours it often does not (see the guide's "Models" (docs/guide/conventions.md)), which
// is why it is not shipped.
std::vector<double> log_smooth(const Spectralizer& linear, const Xyz& target, double tau,
                               bool& converged) {
  const auto& c = linear.weights().columns();
  const std::size_t n = c.size();
  std::vector<double> y(n);
  const SpectrumResult start = linear.spectralize_target(target);
  for (std::size_t i = 0; i < n; ++i) y[i] = std::log(std::max(start.values[i], 1e-4));
  const Roughness rough = Roughness::of_length(tau, linear.settings().grid.step());
  auto residual = [&](const std::vector<double>& v) {
    Xyz r = target;
    for (std::size_t i = 0; i < n; ++i) r = r - std::exp(v[i]) * c[i];
    return r.max_abs() / target.max_abs();
  };
  converged = false;
  for (int it = 0; it < 50; ++it) {
    if (residual(y) < 1e-12) {
      converged = true;
      break;
    }
    // t' = target - W rho + sum rho_i c_i y_i, in z = -y': sum (-rho_i c_i) z_i = t'.
    std::vector<Xyz> cols(n);
    for (std::size_t i = 0; i < n; ++i) cols[i] = -std::exp(y[i]) * c[i];
    Xyz t = target;
    for (std::size_t i = 0; i < n; ++i) {
      const double x = std::exp(y[i]);
      t = t - x * c[i] + (x * y[i]) * c[i];
    }
    const SmoothSpectrum z = SmoothSolver(cols, rough).solve(t);
    std::vector<double> next(n);
    double step = 1;
    for (int k = 0; k < 30; ++k, step *= 0.5) {
      for (std::size_t i = 0; i < n; ++i) next[i] = y[i] + step * (-z.values[i] - y[i]);
      if (residual(next) < std::max(10 * residual(y), 1e-3)) break;  // full steps near a solution
    }
    y = next;
  }
  for (double& v : y) v = std::exp(v);
  return y;
}

}  // namespace

int main(int argc, char** argv) {
  const WavelengthGrid grid = WavelengthGrid::parse(argc > 1 ? argv[1] : "380:780:5");
  const Observer& obs = Observer::get("cie1931");
  const char* file = "colorchecker_n_ohta_5nm.csv";
  std::vector<std::vector<double>> patches;
  for (const std::string& name : embedded_columns(file)) {
    auto [nm, v] = embedded_column(file, name);
    patches.push_back(resample(nm, v, grid));
  }
  const Illuminant a = Illuminant::get("A"), fl11 = Illuminant::get("FL11");
  const SampleWeights under_a(grid, obs, &a), under_fl11(grid, obs, &fl11);
  std::vector<Method> methods = {{"paper (auto filter)", "paper", 0}};
  for (double tau : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 80.0, 100.0})
    methods.push_back(
        {"smooth, tau " + std::to_string(static_cast<int>(tau)) + " nm", "smooth", tau});
  // Curvature alone (slope weight 1e-6 of it): tau = 10 um.
  methods.push_back({"smooth, curvature only", "smooth", 1e4});
  for (double tau : {0.0, 20.0, 50.0})
    methods.push_back(
        {"log smooth, tau " + std::to_string(static_cast<int>(tau)) + " nm", "smooth", tau, true});
  std::printf("%zu patches, grid %s, CIE 1931; dE2000 median / p95 / max\n", patches.size(),
              grid.to_string().c_str());
  std::printf("%-28s | %-20s | %-20s | %-8s | %-9s | %s\n", "method", "under A", "under FL11",
              "RMSE", "max err", "us/solve");
  for (const Method& m : methods) {
    SpectralizerSettings s;
    s.grid = grid;
    s.mode = Mode::reflectance;
    s.model = m.model;
    s.curvature_nm = m.tau_nm;
    const Spectralizer sp(s);
    std::vector<double> de_a, de_f;
    double rmse = 0, worst = 0, seconds = 0;
    for (const auto& rho : patches) {
      const Xyz target = sp.weights().integrate(rho);  // the patch under D65
      const auto t0 = std::chrono::steady_clock::now();
      SpectrumResult r = sp.spectralize_target(target);
      if (m.log) {
        bool converged = false;
        r.values = log_smooth(sp, target, m.tau_nm, converged);
        r.relative_error =
            converged ? relative_error(sp.weights().integrate(r.values), target) : 1.0;
      }
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      worst = std::max(worst, r.relative_error);
      for (const auto* w : {&under_a, &under_fl11}) {
        const double de = delta_e_2000(to_lab(w->integrate(rho), w->unit_white()),
                                       to_lab(w->integrate(r.values), w->unit_white()));
        (w == &under_a ? de_a : de_f).push_back(de);
      }
      double e = 0;
      for (std::size_t i = 0; i < rho.size(); ++i) e += std::pow(r.values[i] - rho[i], 2);
      rmse += std::sqrt(e / static_cast<double>(rho.size())) / static_cast<double>(patches.size());
    }
    std::printf("%-28s | %5.2f / %5.2f / %5.2f | %5.2f / %5.2f / %5.2f | %8.4f | %9.1e | %.1f\n",
                m.name.c_str(), percentile(de_a, 0.5), percentile(de_a, 0.95),
                *std::max_element(de_a.begin(), de_a.end()), percentile(de_f, 0.5),
                percentile(de_f, 0.95), *std::max_element(de_f.begin(), de_f.end()), rmse, worst,
                1e6 * seconds / static_cast<double>(patches.size()));
  }
}
