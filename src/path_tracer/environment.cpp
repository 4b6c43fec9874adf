#include "path_tracer/environment.h"

#include <algorithm>
#include <numbers>
#include <string>

#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

namespace {

constexpr double kPi = std::numbers::pi;

// The index i with cdf[i] <= u < cdf[i + 1] among intervals of positive width (cdf increasing
// from 0 to 1).
int find_interval(const double* cdf, int n, double u) {
  const int i = static_cast<int>(std::upper_bound(cdf + 1, cdf + n + 1, u) - (cdf + 1));
  return std::min(i, n - 1);
}

}  // namespace

Environment::Environment(int width, int height, std::vector<Xyz> xyz)
    : w_(width), h_(height), xyz_(std::move(xyz)) {
  if (w_ < 2 || h_ < 2 || xyz_.size() != static_cast<std::size_t>(w_) * h_)
    throw Error("environment map: need >= 2 x 2 texels and one colour each (got " +
                std::to_string(w_) + " x " + std::to_string(h_) + ", " +
                std::to_string(xyz_.size()) + " colours)");
  // Texel weights: luminance times the texel's solid angle (proportional to sin theta).
  std::vector<double> weight(xyz_.size());
  row_cdf_.assign(h_ + 1, 0.0);
  column_cdf_.assign(static_cast<std::size_t>(h_) * (w_ + 1), 0.0);
  for (int y = 0; y < h_; ++y) {
    const double sin_theta = std::sin((y + 0.5) / h_ * kPi);
    double* cdf = &column_cdf_[static_cast<std::size_t>(y) * (w_ + 1)];
    for (int x = 0; x < w_; ++x) {
      const std::size_t t = static_cast<std::size_t>(y) * w_ + x;
      weight[t] = std::max(0.0, xyz_[t].Y) * sin_theta;
      cdf[x + 1] = cdf[x] + weight[t];
    }
    row_cdf_[y + 1] = row_cdf_[y] + cdf[w_];
    if (cdf[w_] > 0)
      for (int x = 1; x <= w_; ++x) cdf[x] /= cdf[w_];
  }
  const double total = row_cdf_[h_];
  if (!(total > 0)) throw Error("environment map: no texel has a positive luminance");
  for (double& c : row_cdf_) c /= total;
  texel_pmf_.resize(weight.size());
  for (std::size_t t = 0; t < weight.size(); ++t) texel_pmf_[t] = weight[t] / total;
}

Vec3 Environment::direction_of(double u, double v) const {
  const double phi = 2 * kPi * u, theta = kPi * v;
  const double s = std::sin(theta);
  return {std::sin(phi) * s, std::cos(theta), -std::cos(phi) * s};
}

std::uint32_t Environment::texel(const Vec3& d) const {
  double u = std::atan2(d.x, -d.z) / (2 * kPi);
  if (u < 0) u += 1;
  const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
  const int x = std::clamp(static_cast<int>(u * w_), 0, w_ - 1);
  const int y = std::clamp(static_cast<int>(v * h_), 0, h_ - 1);
  return static_cast<std::uint32_t>(y * w_ + x);
}

EnvironmentSample Environment::sample(double u1, double u2, double u3, double u4) const {
  const int y = find_interval(row_cdf_.data(), h_, u1);
  const int x = find_interval(&column_cdf_[static_cast<std::size_t>(y) * (w_ + 1)], w_, u2);
  const double u = (x + u3) / w_, v = (y + u4) / h_;
  EnvironmentSample s;
  s.direction = direction_of(u, v);
  s.texel = static_cast<std::uint32_t>(y * w_ + x);
  const double sin_theta = std::sin(kPi * v);
  // Uniform in (u, v) inside the texel: density pmf * w * h per unit (u, v); the map's
  // (u, v) -> direction has Jacobian 2 pi^2 sin theta.
  s.pdf = sin_theta > 0 ? texel_pmf_[s.texel] * w_ * h_ / (2 * kPi * kPi * sin_theta) : 0.0;
  return s;
}

double Environment::pdf(const Vec3& d) const {
  const double sin_theta = std::sqrt(std::max(0.0, 1 - d.y * d.y));
  if (!(sin_theta > 0)) return 0;
  return texel_pmf_[texel(d)] * w_ * h_ / (2 * kPi * kPi * sin_theta);
}

Xyz Environment::white_up() const {
  // Per texel: radiance * the integral of cos theta over the texel's solid angle, in closed form
  // over theta (int sin cos = (sin^2 b - sin^2 a) / 2), times its width in phi; then / pi.
  Xyz sum;
  for (int y = 0; y < h_; ++y) {
    const double a = kPi * y / h_, b = kPi * (y + 1) / h_;
    if (a >= kPi / 2) break;
    const double bb = std::min(b, kPi / 2);
    const double cos_area =
        (std::sin(bb) * std::sin(bb) - std::sin(a) * std::sin(a)) / 2 * (2 * kPi / w_);
    for (int x = 0; x < w_; ++x) sum = sum + cos_area * xyz_[static_cast<std::size_t>(y) * w_ + x];
  }
  return (1 / kPi) * sum;
}

}  // namespace spectralize::path_tracer
