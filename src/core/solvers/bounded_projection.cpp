#include "core/solvers/bounded_projection.h"

#include <cmath>

namespace spectralize {

namespace {

// Primitive of clamp(z, 0, upper), so that the dual objective below is smooth and convex.
double clamp_primitive(double z, double upper) {
  if (z <= 0) return 0;
  if (z <= upper) return 0.5 * z * z;
  return 0.5 * upper * upper + upper * (z - upper);
}

struct Sym3 {
  double a[3][3] = {};
};

// Solves (H + mu I) d = rhs for a symmetric positive semidefinite H by Cholesky; mu > 0 damps
// the directions in which H is singular (few or no free samples).
Xyz solve_regularised(const Sym3& h, const Xyz& rhs, double mu) {
  double l[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) {
      double sum = h.a[i][j] + (i == j ? mu : 0.0);
      for (int k = 0; k < j; ++k) sum -= l[i][k] * l[j][k];
      if (i == j)
        l[i][i] = std::sqrt(std::max(sum, mu));
      else
        l[i][j] = sum / l[j][j];
    }
  Xyz y, x;
  for (int i = 0; i < 3; ++i) {
    double sum = rhs[i];
    for (int k = 0; k < i; ++k) sum -= l[i][k] * y[k];
    y[i] = sum / l[i][i];
  }
  for (int i = 2; i >= 0; --i) {
    double sum = y[i];
    for (int k = i + 1; k < 3; ++k) sum -= l[k][i] * x[k];
    x[i] = sum / l[i][i];
  }
  return x;
}

}  // namespace

bool polish_exact(std::span<const Xyz> weights, std::span<double> spectrum, const Xyz& target) {
  const std::size_t n = weights.size();
  std::vector<double> x(spectrum.begin(), spectrum.end());
  const double tol = 1e-14 * std::max(target.max_abs(), 1e-300);
  for (int iteration = 0; iteration < 4; ++iteration) {
    Xyz residual = target;
    for (std::size_t m = 0; m < n; ++m) residual = residual - x[m] * weights[m];
    if (residual.max_abs() <= tol) break;
    // G = sum_m x_m c_m c_m^T / s_m (symmetric): W (x * (1 + C^T a / s)) = W x + G a.
    Sym3 g;
    for (std::size_t m = 0; m < n; ++m) {
      const Xyz& c = weights[m];
      double s = c.sum();
      if (!(s > 0) || x[m] == 0) continue;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) g.a[i][j] += x[m] * c[i] * c[j] / s;
    }
    double trace = g.a[0][0] + g.a[1][1] + g.a[2][2];
    if (!(trace > 0)) return false;
    Xyz a = solve_regularised(g, residual, 1e-15 * trace);
    for (std::size_t m = 0; m < n; ++m) {
      double s = weights[m].sum();
      if (!(s > 0)) continue;
      double factor = 1 + dot(weights[m], a) / s;
      if (!(factor >= 0)) return false;  // too large a change to be a polish
      x[m] *= factor;
    }
  }
  Xyz residual = target;
  for (std::size_t m = 0; m < n; ++m) residual = residual - x[m] * weights[m];
  if (!(residual.max_abs() <= 1e-12 * std::max(target.max_abs(), 1e-300))) return false;
  std::copy(x.begin(), x.end(), spectrum.begin());
  return true;
}

Projection project_exact(std::span<const Xyz> weights, std::span<const double> start,
                         const Xyz& target, double upper, const ProjectionControl& control) {
  std::vector<double> bounds(weights.size(), upper);
  return project_exact(weights, start, target, bounds, control);
}

Projection project_exact(std::span<const Xyz> weights, std::span<const double> start,
                         const Xyz& target, std::span<const double> upper_bounds,
                         const ProjectionControl& control) {
  const std::size_t n = weights.size();
  Projection out;
  out.values.resize(n);
  const double scale = std::max(target.max_abs(), 1e-300);
  const double tol = control.tolerance * scale;

  // Dual objective psi(nu) = sum_m P(start_m + c_m.nu) - target.nu; its gradient is
  // W x(nu) - target, so a minimiser gives an exact x.
  auto evaluate = [&](const Xyz& nu, Xyz& grad, Sym3* hess) {
    double psi = -dot(target, nu);
    grad = Xyz{} - target;
    for (std::size_t m = 0; m < n; ++m) {
      const Xyz& c = weights[m];
      const double upper = upper_bounds[m];
      double z = start[m] + dot(c, nu);
      psi += clamp_primitive(z, upper);
      double x = std::min(std::max(z, 0.0), upper);
      out.values[m] = x;
      grad = grad + x * c;
      if (hess && z > 0 && z < upper)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) hess->a[i][j] += c[i] * c[j];
    }
    return psi;
  };

  // Scale of the problem: the trace of W W^T bounds the curvature of psi (its gradient's
  // Lipschitz constant), which sizes both the damping and the safe gradient step.
  double lipschitz = 0;
  for (const Xyz& c : weights) lipschitz += dot(c, c);
  const double mu = control.damping * lipschitz + 1e-300;

  Xyz nu, grad;
  Sym3 hess;
  evaluate(nu, grad, &hess);
  for (out.iterations = 0; out.iterations < control.max_iterations; ++out.iterations) {
    if (grad.max_abs() <= tol) {
      out.converged = true;
      out.residual = grad.max_abs() / scale;
      return out;
    }
    // Damped Newton direction on the free set (or the gradient, if that is no descent), then
    // an exact line search on the directional derivative step . grad(nu + t step), which
    // increases with t (psi is convex): bisection on its sign. Working on gradients, not on
    // psi's values, keeps it accurate when psi is large and its decrease is tiny (targets near
    // the boundary of the feasible set).
    Xyz step = solve_regularised(hess, Xyz{} - grad, mu);
    if (!(dot(grad, step) < 0)) step = (-1.0 / lipschitz) * grad;
    if (!(dot(grad, step) < 0)) break;
    Xyz g;
    Sym3 h;
    double t = 1.0;
    evaluate(nu + step, g, &h);
    if (dot(g, step) > 0) {
      double lo = 0, hi = 1;
      for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        evaluate(nu + mid * step, g, nullptr);
        (dot(g, step) > 0 ? hi : lo) = mid;
      }
      t = lo;             // the last point where psi still descends
      if (t == 0) break;  // no progress possible in this direction
      h = Sym3{};
      evaluate(nu + t * step, g, &h);
    }
    nu = nu + t * step;
    grad = g;
    hess = h;
  }
  evaluate(nu, grad, nullptr);
  out.converged = grad.max_abs() <= tol;
  out.residual = grad.max_abs() / scale;
  return out;
}

}  // namespace spectralize
