#include "baseline/sigmoid_spectrum.h"

#include <algorithm>
#include <atomic>
#include <thread>

#include "core/colorimetry/colour_difference.h"
#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize::baseline {

namespace {

constexpr double kMinNm = 360.0, kRangeNm = 470.0;  // t = (nm - 360) / 470

SampleWeights reflectance_weights(const WavelengthGrid& grid, const std::string& observer,
                                  const std::string& illuminant) {
  const Illuminant il = Illuminant::get(illuminant);
  return SampleWeights(grid, Observer::get(observer), &il);
}

// Derivative of CIELAB's f (cube root joined by a line below (6/29)^3, as to_lab uses).
double lab_f_prime(double t) {
  constexpr double delta = 6.0 / 29.0;
  if (t > delta * delta * delta) {
    const double c = std::cbrt(t);
    return 1.0 / (3 * c * c);
  }
  return 1.0 / (3 * delta * delta);
}

using Mat3 = std::array<std::array<double, 3>, 3>;

// Solves m x = v by Cramer's rule; false when m is singular.
bool solve3(const Mat3& m, const std::array<double, 3>& v, std::array<double, 3>& x) {
  const auto det = [](const Mat3& a) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const double d = det(m);
  if (!(std::abs(d) > 0) || !std::isfinite(d)) return false;
  for (int c = 0; c < 3; ++c) {
    Mat3 mc = m;
    for (int r = 0; r < 3; ++r) mc[r][c] = v[r];
    x[c] = det(mc) / d;
  }
  return true;
}

double norm2(const std::array<double, 3>& v) {
  return v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
}

double smoothstep(double x) {
  return x * x * (3 - 2 * x);
}

}  // namespace

BasicSigmoidPolynomial<double> to_nm(const std::array<double, 3>& n) {
  // a t^2 + b t + c with t = (nm - L) / D, expanded in nm.
  const double a = n[0], b = n[1], c = n[2], L = kMinNm, D = kRangeNm;
  return {a / (D * D), b / D - 2 * a * L / (D * D), c - b * L / D + a * L * L / (D * D)};
}

SigmoidFitter::SigmoidFitter(const RgbToXyz& rgb_to_xyz, const SigmoidFitterSettings& settings)
    : rgb_to_xyz_(rgb_to_xyz),
      grid_(settings.grid),
      weights_(reflectance_weights(settings.grid, settings.observer, settings.illuminant)),
      balance_(balance_from_d65(weights_.unit_white())),
      t_(grid_.size()),
      max_coefficient_(settings.max_coefficient) {
  if (!(max_coefficient_ > 0))
    throw Error("sigmoid fit: max_coefficient must be positive (infinity: no bound)");
  for (std::size_t i = 0; i < grid_.size(); ++i) t_[i] = (grid_[i] - kMinNm) / kRangeNm;
}

Xyz SigmoidFitter::target_of(const std::array<double, 3>& rgb) const {
  Xyz xyz;
  for (int r = 0; r < 3; ++r)
    xyz[r] = rgb_to_xyz_[r][0] * rgb[0] + rgb_to_xyz_[r][1] * rgb[1] + rgb_to_xyz_[r][2] * rgb[2];
  return hadamard(xyz, balance_);
}

std::vector<double> SigmoidFitter::spectrum(const BasicSigmoidPolynomial<double>& p) const {
  std::vector<double> s(grid_.size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i] = p(grid_[i]);
  return s;
}

Xyz SigmoidFitter::xyz_of(const BasicSigmoidPolynomial<double>& p) const {
  return weights_.integrate(spectrum(p));
}

SigmoidFit SigmoidFitter::fit(const std::array<double, 3>& rgb, const std::array<double, 3>& start,
                              int max_iterations) const {
  const Xyz white = weights_.unit_white();
  const Lab goal = to_lab(target_of(rgb), white);
  const auto& w = weights_.columns();

  // Residual Lab(s(c)) - goal and, if `jac`, its Jacobian in the normalised coefficients: the
  // XYZ of the grid samples through the reference weights (docs/DESIGN.md §3), then CIELAB.
  const auto evaluate = [&](const std::array<double, 3>& c, Mat3* jac) {
    Xyz xyz;
    Mat3 dxyz{};  // d XYZ_r / d c_q
    for (std::size_t i = 0; i < t_.size(); ++i) {
      const double t = t_[i], x = (c[0] * t + c[1]) * t + c[2];
      const double q = 1 / (1 + x * x), r = std::sqrt(q);
      const double s = 0.5 + 0.5 * x * r;  // 1/2 + x / (2 sqrt(1 + x^2))
      xyz = xyz + s * w[i];
      if (jac) {
        const double ds = 0.5 * q * r;  // ds/dx = 1 / (2 (1 + x^2)^(3/2))
        const double basis[3] = {t * t, t, 1};
        for (int k = 0; k < 3; ++k)
          for (int b = 0; b < 3; ++b) dxyz[k][b] += w[i][k] * ds * basis[b];
      }
    }
    const Lab lab = to_lab(xyz, white);
    if (jac) {
      const double fx = lab_f_prime(xyz.X / white.X) / white.X;
      const double fy = lab_f_prime(xyz.Y / white.Y) / white.Y;
      const double fz = lab_f_prime(xyz.Z / white.Z) / white.Z;
      for (int b = 0; b < 3; ++b) {
        (*jac)[0][b] = 116 * fy * dxyz[1][b];
        (*jac)[1][b] = 500 * (fx * dxyz[0][b] - fy * dxyz[1][b]);
        (*jac)[2][b] = 200 * (fy * dxyz[1][b] - fz * dxyz[2][b]);
      }
    }
    return std::array<double, 3>{lab.L - goal.L, lab.a - goal.a, lab.b - goal.b};
  };

  // Levenberg-Marquardt: the Gauss-Newton step of rgb2spec, damped only when it fails to
  // decrease the residual (the curve is flat far out on the sigmoid).
  SigmoidFit out;
  std::array<double, 3> c = start;
  Mat3 jac;
  std::array<double, 3> r = evaluate(c, &jac);
  double cost = norm2(r), lambda = 0;
  int it = 0;
  while (it < max_iterations && cost > 1e-12) {
    ++it;
    Mat3 a{};
    std::array<double, 3> g{};
    double diag_max = 0;
    for (int p = 0; p < 3; ++p) {
      for (int q = 0; q < 3; ++q)
        for (int k = 0; k < 3; ++k) a[p][q] += jac[k][p] * jac[k][q];
      for (int k = 0; k < 3; ++k) g[p] -= jac[k][p] * r[k];
      diag_max = std::max(diag_max, a[p][p]);
    }
    for (int p = 0; p < 3; ++p) a[p][p] += lambda * diag_max;
    std::array<double, 3> step;
    bool accepted = false;
    if (solve3(a, g, step)) {
      std::array<double, 3> trial = {c[0] + step[0], c[1] + step[1], c[2] + step[2]};
      // rgb2spec's bound: the largest coefficient stays <= max_coefficient, scaling all three
      // (the zero crossings stay). Colours the sigmoid cannot reach drive the coefficients to
      // infinity (a box spectrum, where the Jacobian vanishes and float evaluation fails).
      const double largest = std::max({trial[0], trial[1], trial[2]});
      if (largest > max_coefficient_)
        for (double& v : trial) v *= max_coefficient_ / largest;
      Mat3 trial_jac;
      const std::array<double, 3> trial_r = evaluate(trial, &trial_jac);
      const double trial_cost = norm2(trial_r);
      if (trial_cost < cost) {
        c = trial, r = trial_r, jac = trial_jac, cost = trial_cost;
        lambda = lambda > 1e-9 ? lambda / 4 : 0;
        accepted = true;
      }
    }
    if (!accepted) {
      if (lambda > 1e8) break;  // no descent left: the least-squares point
      lambda = lambda == 0 ? 1e-6 : lambda * 8;
    }
  }
  out.normalised = c;
  out.polynomial = to_nm(c);
  out.delta_e76 = std::sqrt(cost);
  out.iterations = it;
  return out;
}

SigmoidTable::SigmoidTable(const SigmoidFitter& fitter, int resolution, int threads)
    : res_(resolution) {
  if (res_ < 2) throw Error("sigmoid table: resolution must be at least 2");
  const std::size_t res = static_cast<std::size_t>(res_);
  z_nodes_.resize(res);
  for (int k = 0; k < res_; ++k)
    z_nodes_[k] = static_cast<float>(smoothstep(smoothstep(k / double(res_ - 1))));
  coefficients_.assign(9 * res * res * res, 0.0f);

  const int mid = (res_ - 1) / 2;
  const auto rgb_of = [&](int m, int k, int j, int i) {
    const double z = z_nodes_[k];
    std::array<double, 3> rgb;
    rgb[m] = z;
    rgb[(m + 1) % 3] = z * (i / double(res_ - 1));
    rgb[(m + 2) % 3] = z * (j / double(res_ - 1));
    return rgb;
  };
  const auto store = [&](int m, int k, int j, int i, const SigmoidFit& f) {
    float* c = coefficients_.data() + 3 * (((m * res + k) * res + j) * res + i);
    c[0] = static_cast<float>(f.polynomial.c0);
    c[1] = static_cast<float>(f.polynomial.c1);
    c[2] = static_cast<float>(f.polynomial.c2);
  };

  // Seeds at the middle of the z range on the grey edge x = 1, from y = 1 (grey) down.
  std::vector<std::array<double, 3>> seeds(3 * res);
  for (int m = 0; m < 3; ++m) {
    std::array<double, 3> c{};
    for (int j = res_ - 1; j >= 0; --j)
      c = seeds[m * res + j] = fitter.fit(rgb_of(m, mid, j, res_ - 1), c).normalised;
  }

  // One task per (block, y row): x inward from the seed at mid z, z outward from each.
  std::atomic<int> next{0};
  std::vector<double> worst(static_cast<std::size_t>(std::max(threads, 1)), 0.0);
  const auto work = [&](int worker) {
    for (int task; (task = next++) < 3 * res_;) {
      const int m = task / res_, j = task % res_;
      std::array<double, 3> row = seeds[task];
      for (int i = res_ - 1; i >= 0; --i) {
        const SigmoidFit f = fitter.fit(rgb_of(m, mid, j, i), row);
        row = f.normalised;
        store(m, mid, j, i, f);
        worst[worker] = std::max(worst[worker], f.delta_e76);
        for (int dir : {1, -1}) {
          std::array<double, 3> c = row;
          for (int k = mid + dir; k >= 0 && k < res_; k += dir) {
            const SigmoidFit g = fitter.fit(rgb_of(m, k, j, i), c);
            c = g.normalised;
            store(m, k, j, i, g);
            worst[worker] = std::max(worst[worker], g.delta_e76);
          }
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < static_cast<int>(worst.size()); ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& t : pool) t.join();
  max_node_delta_e_ = *std::max_element(worst.begin(), worst.end());
}

}  // namespace spectralize::baseline
