#include "core/solvers/natural_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/multiversion.h"
#include "core/solvers/bounded_projection.h"

namespace spectralize {

namespace {

// Newton iterations before giving up (typical colours take 5..10, targets at the natural
// depth 0.999 up to ~25; the cap only guards against the unforeseen).
constexpr int kNewtonIterations = 80;
// Largest change of any z_i in one Newton step (a trust region in the link's units: the odds
// ratio of a sample changes by at most e^8 per step). Full Newton steps from the grey start can
// jump far past the solution into saturation, where sigma' underflows and the Jacobian
// degenerates. A safeguard, not a model parameter: in the NumPy exploration (explore/robust2.py)
// limits of 1 and 2 left 3-4% of targets 1e-6 inside the solid unconverged; 0.5 and 4 none,
// 4 in fewer steps (median 17 against 23).
constexpr double kMaxStep = 4.0;
// Newton has converged when a full step moves no z_i by more than this (quadratic
// convergence: the next step would be ~1e-16).
constexpr double kStepTolerance = 1e-9;
// Proximal (Levenberg) term added to the Hessian of the Lagrangian: makes the roughness
// Hessian (singular along constants) definite without moving the solution (it damps the step,
// not the stationarity condition). H's entries are O(1) (2 on the diagonal).
constexpr double kRidge = 2e-9;
// Relative size below which an eigenvalue of the 3x3 Schur complement counts as zero (its
// direction is left out of the multiplier step: a pseudo-inverse).
constexpr double kSchurFloor = 1e-14;
// Levenberg damping of the dual Newton step, relative to the Hessian's trace: only guards
// against an exactly singular Hessian. Larger values (1e-14 was tried) stop the dual from
// correcting the nearly flat direction of purples near the locus.
constexpr double kDualDamping = 1e-20;
// The damping of the safety net's second try (relative to the trace of W W^T).
constexpr double kSafetyDamping = 1e-12;
// The projection's cap: it is a finite-termination method (active sets), typically 1..10.
constexpr int kProjectionIterations = 200;
static_assert(NaturalSolver::kMaxIterations == kNewtonIterations + 3 * kProjectionIterations,
              "the stated cap is the loops' caps");
// Exactness aimed at by the projections (max|W x - t| / max|t|), and the one accepted when
// they stall short of it (the model's contract: 1e-12).
constexpr double kExact = 1e-13;
constexpr double kAccept = 1e-12;

// The link x = L(z) and its first two derivatives, per sample.
struct Link {
  double x, d1, d2;
};

// Reflectance: x = upper * sigma(z), sigma = (tanh z + 1)/2 = 1 / (1 + e^{-2z}), evaluated
// from e^{-2|z|} so that neither x nor upper - x loses relative precision in saturation.
// Light: x = e^z.
Link link(double z, double upper) {
  if (!std::isfinite(upper)) {
    const double e = std::exp(z);
    return {e, e, e};
  }
  const double e = std::exp(-2.0 * std::abs(z));
  const double big = 1.0 / (1.0 + e), small = e / (1.0 + e);  // sigma(|z|), 1 - sigma(|z|)
  const double s = z >= 0 ? big : small;                      // sigma(z)
  const double d1 = 2.0 * big * small;                        // sigma' = 2 sigma (1 - sigma)
  const double d2 = 2.0 * d1 * (z >= 0 ? small - big : big - small);  // 2 sigma' (1 - 2 sigma)
  return {upper * s, upper * d1, upper * d2};
}

// Inverse of the link for a grey level: the constant z whose spectrum has luminance fraction p
// of the white (reflectance, p in (0, 1)) or that scale p of the white (light, p > 0).
double grey_link(double p, double upper) {
  if (!std::isfinite(upper)) return std::log(p);
  return 0.5 * std::log(p / (1.0 - p));
}

// Newton's method on the Lagrangian of  min 1/2 sum (z_{i+1} - z_i)^2  s.t.  W L(z) = t.
// Stationarity: H z = L'(z) .* (W^T lambda), H = D^T D tridiagonal. Each step solves
//   [A  -J^T] [dz]   [-g]        A = H - diag(L''(z) .* W^T lambda) (+ ridge),
//   [J    0 ] [dl] = [ r],       J = W diag(L'(z)), g = H z - J^T lambda, r = t - W L(z),
// by a tridiagonal LDL^T of A and the 3x3 Schur complement S = J A^-1 J^T. Where the KKT
// matrix lacks the inertia of a minimum (far from the solution the constraint curvature term
// can make A indefinite), A is shifted to be positive definite, which keeps the step a descent
// direction; near the solution the exact step is taken (quadratic convergence).
// Returns true when a full step smaller than kStepTolerance was taken; z holds the iterate.
bool natural_newton(std::span<const Xyz> w, const Xyz& t, double upper, std::vector<double>& z,
                    int& iterations) {
  const int n = static_cast<int>(w.size());
  std::vector<Link> l(n);
  std::vector<double> h0(n), curvature(n), piv(n), lower(n);
  std::vector<std::array<double, 4>> y(n);  // A^-1 [-g, J_X^T, J_Y^T, J_Z^T]
  std::vector<std::array<double, 4>> rhs0(n);
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
  for (int it = 0; it < kNewtonIterations; ++it) {
    ++iterations;
    Xyz r = t;
    for (int i = 0; i < n; ++i) {
      l[i] = link(z[i], upper);
      r = r - l[i].x * w[i];
    }
    bool indefinite = false;  // some curvature term -L'' a_i is negative
    for (int i = 0; i < n; ++i) {
      const double a = w[i].X * lambda[0] + w[i].Y * lambda[1] + w[i].Z * lambda[2];
      const double hz = (i > 0 ? z[i] - z[i - 1] : 0.0) + (i + 1 < n ? z[i] - z[i + 1] : 0.0);
      h0[i] = (i > 0 ? 1.0 : 0.0) + (i + 1 < n ? 1.0 : 0.0) + kRidge;
      curvature[i] = -l[i].d2 * a;
      indefinite |= curvature[i] < 0;
      const double jx = l[i].d1;
      y[i] = {-(hz - jx * a), jx * w[i].X, jx * w[i].Y, jx * w[i].Z};
      rhs0[i] = y[i];
    }
    // Tridiagonal LDL^T of A (off-diagonal -1), pivots of either sign. The exact Newton step
    // is used when the KKT matrix has the inertia of a minimum (the Hessian positive on the
    // constraints' tangent space: A's negative pivots matched by as many negative eigenvalues
    // of S, Gould's test); otherwise the negative curvature terms are dropped (A = H + the
    // positive ones + ridge, positive definite), which makes the step a descent direction.
    Eigen::Vector3d dl;
    bool solved = false;
    for (int attempt = 0; attempt < 2 && !solved; ++attempt) {
      const bool convex = attempt == 1;
      if (convex) {
        if (!indefinite) break;
        for (int i = 0; i < n; ++i) y[i] = rhs0[i];
      }
      int negative = 0;
      bool factored = true;
      for (int i = 0; i < n; ++i) {
        double d = h0[i] + (convex ? std::max(curvature[i], 0.0) : curvature[i]);
        if (i > 0) d -= lower[i - 1] * lower[i - 1] * piv[i - 1];
        if (!(std::abs(d) > 1e-12)) {
          factored = false;
          break;
        }
        negative += d < 0;
        piv[i] = d;
        lower[i] = -1.0 / d;  // L_{i+1,i} = A_{i+1,i} / d_i
      }
      if (!factored || negative > 3) continue;
      // Forward, diagonal, backward substitution for the four right-hand sides at once.
      for (int i = 1; i < n; ++i)
        for (int q = 0; q < 4; ++q) y[i][q] -= lower[i - 1] * y[i - 1][q];
      for (int i = 0; i < n; ++i)
        for (int q = 0; q < 4; ++q) y[i][q] /= piv[i];
      for (int i = n - 2; i >= 0; --i)
        for (int q = 0; q < 4; ++q) y[i][q] -= lower[i] * y[i + 1][q];
      // Schur complement: S dl = r - J y0, then dz = y0 + Y dl.
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      Eigen::Vector3d rhs(r.X, r.Y, r.Z);
      for (int i = 0; i < n; ++i) {
        const double jx = l[i].d1;
        const Eigen::Vector3d ji(jx * w[i].X, jx * w[i].Y, jx * w[i].Z);
        rhs -= ji * y[i][0];
        s += ji * Eigen::RowVector3d(y[i][1], y[i][2], y[i][3]);
      }
      s = 0.5 * (s + s.transpose()).eval();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(s);
      if (eig.info() != Eigen::Success) continue;
      const Eigen::Vector3d ev = eig.eigenvalues();
      const double big = ev.cwiseAbs().maxCoeff();
      if (!(big > 0)) continue;
      int s_negative = 0;
      Eigen::Vector3d inv;
      for (int q = 0; q < 3; ++q) {
        s_negative += ev[q] < 0;
        // A near-null direction of S (constraints barely controllable, e.g. only the violet
        // end lit) gets a bounded multiplier step instead of an unbounded one.
        inv[q] = std::abs(ev[q]) > kSchurFloor * big ? 1.0 / ev[q] : 0.0;
      }
      if (s_negative != negative) continue;
      dl = eig.eigenvectors() * (inv.asDiagonal() * (eig.eigenvectors().transpose() * rhs));
      solved = dl.allFinite();
    }
    if (!solved) return false;
    double largest = 0;
    for (int i = 0; i < n; ++i) {
      y[i][0] += y[i][1] * dl[0] + y[i][2] * dl[1] + y[i][3] * dl[2];
      largest = std::max(largest, std::abs(y[i][0]));
    }
    if (!std::isfinite(largest)) return false;
    const double step = largest > kMaxStep ? kMaxStep / largest : 1.0;
    double size = 1.0;
    for (int i = 0; i < n; ++i) {
      z[i] += step * y[i][0];
      size = std::max(size, std::abs(z[i]));
    }
    lambda += step * dl;
    if (step == 1.0 && largest <= kStepTolerance * size) return true;
  }
  return false;
}

// The exact spectrum nearest to L(z0) in the link's own geometry: z = z0 + W^T nu, nu
// minimising the smooth strictly convex dual psi(nu) = sum Lambda(z0_i + W_i . nu) - t . nu
// (Lambda' = L: (upper/2) log(1 + e^{2z}) or e^z), whose gradient is W L(z) - t. For lights
// this is the Kullback-Leibler projection of e^{z0} onto {W x = t}; for reflectances the
// Fermi-Dirac (binary entropy) projection onto {W x = t, 0 < x < upper}. So the result stays inside
// the bounds by construction, stays in the natural family's form (smooth z plus a combination of
// the three weight rows), is continuous in (z0, t), is z0 itself when L(z0) is already exact, and
// exists for every target strictly inside the gamut (psi is coercive there). Newton on nu with a
// safeguarded line search on the directional derivative (monotone, psi being convex). `z` holds z0
// on entry, the projected link on exit. Returns true when exact to kAccept. Cost: O(N) per
// iteration, typically 1 (a polish) to ~30 (near the boundary).
bool link_projection(std::span<const Xyz> w, std::vector<double>& z, const Xyz& t, double upper,
                     int& iterations) {
  const std::size_t n = w.size();
  const double tol = kExact * std::max(t.max_abs(), 1e-300);
  // Gradient W L(z + a W^T d) - t (and the Hessian sum L'(.) W_i W_i^T) along a step d. The
  // dual variable is folded into z after every step (z += a W^T d, i.e. nu re-centred at 0):
  // near the locus nu reaches ~1e8 while z stays O(10), and evaluating z0 + W^T nu would lose
  // ~1e-11 of z to cancellation.
  auto evaluate = [&](const Xyz& d, double a, Xyz& grad, Eigen::Matrix3d* hess) {
    grad = Xyz{} - t;
    if (hess) hess->setZero();
    for (std::size_t i = 0; i < n; ++i) {
      const Link li = link(z[i] + a * dot(w[i], d), upper);
      grad = grad + li.x * w[i];
      if (hess) {
        const Eigen::Vector3d c(w[i].X, w[i].Y, w[i].Z);
        *hess += li.d1 * (c * c.transpose());
      }
    }
  };
  Xyz grad;
  Eigen::Matrix3d hess;
  evaluate(Xyz{}, 0.0, grad, &hess);
  for (int it = 0; it < kProjectionIterations; ++it) {
    if (grad.max_abs() <= tol) return true;
    ++iterations;
    // Newton direction (the damping only guards against an exactly singular Hessian).
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(hess + (kDualDamping * hess.trace() + 1e-300) *
                                                       Eigen::Matrix3d::Identity());
    const Eigen::Vector3d v = ldlt.solve(-Eigen::Vector3d(grad.X, grad.Y, grad.Z));
    const Xyz step{v[0], v[1], v[2]};
    const double d0 = dot(grad, step);
    if (!step.finite() || !(d0 < 0)) break;
    // phi'(a) = step . grad(a) increases with a (psi is convex): accept the full step if phi'
    // is still <= 0 there, else find its root by regula falsi (Illinois), bisecting while the
    // gradient is not finite (an overflowing light). (Capping the change of z per step, as in
    // Newton above, was tried: near the locus nu must travel ~1e8, so it stalled.)
    Xyz g;
    Eigen::Matrix3d h;
    evaluate(step, 1.0, g, &h);
    double alpha = 1.0;
    if (!(dot(g, step) <= 0)) {
      double lo = 0, hi = 1.0, flo = d0, fhi = dot(g, step);
      int side = 0;
      for (int k = 0; k < 60; ++k) {
        const double mid =
            std::isfinite(fhi) ? (lo * fhi - hi * flo) / (fhi - flo) : 0.5 * (lo + hi);
        evaluate(step, mid, g, nullptr);
        const double fm = dot(g, step);
        if (!(fm > 0)) {
          lo = mid;
          flo = fm;
          if (side == -1) fhi *= 0.5;  // Illinois: halve the stale end
          side = -1;
        } else {
          hi = mid;
          fhi = fm;
          if (side == 1) flo *= 0.5;
          side = 1;
        }
        if (std::abs(fm) <= 1e-3 * std::abs(d0) || hi - lo <= 1e-12 * hi) break;
      }
      alpha = lo > 0 ? lo : 0.5 * hi;
      evaluate(step, alpha, g, &h);
    }
    for (std::size_t i = 0; i < n; ++i) z[i] += alpha * dot(w[i], step);
    grad = g;
    hess = h;
  }
  return grad.max_abs() <= (kAccept / kExact) * tol;
}

// The largest ratio |n_f . d| / (the room from a to facet f on d's side) over the solid's facets:
// the depth of a + d (docs/DESIGN.md §6). Cost: a division per facet (~5 us for the 3240 facets
// of the 5 nm grid).
double max_facet_ratio(const double* nx, const double* ny, const double* nz, const double* pos,
                       const double* neg, std::size_t n, const Xyz& d, const Xyz& a, double upper) {
  double best = 0;
  for (std::size_t f = 0; f < n; ++f) {
    const double nd = nx[f] * d.X + ny[f] * d.Y + nz[f] * d.Z;
    const double na = nx[f] * a.X + ny[f] * a.Y + nz[f] * a.Z;
    // The room is positive: the grey a is strictly inside (depth() ensures it).
    if (nd > 0)
      best = std::max(best, nd / (upper * pos[f] - na));
    else if (nd < 0)
      best = std::max(best, -nd / (upper * neg[f] + na));
  }
  return best;
}

// Whether the depth of a + d exceeds g: some facet with |n_f . d| > g x its room. No division
// and no branch, so the loop is vectorised (compiled for AVX2 and baseline x86-64, picked at
// load time): ~1 us for the 5 nm grid's facets, where the exact depth costs ~5 us. The natural
// zone needs only this test; the exact depth only beyond it (docs/DESIGN.md §6).
SPECTRALIZE_MULTIVERSION_AVX2 bool deeper_than(const double* nx, const double* ny, const double* nz,
                                               const double* pos, const double* neg, std::size_t n,
                                               const Xyz& d, const Xyz& a, double upper, double g) {
  int beyond = 0;
  for (std::size_t f = 0; f < n; ++f) {
    const double nd = nx[f] * d.X + ny[f] * d.Y + nz[f] * d.Z;
    const double na = nx[f] * a.X + ny[f] * a.Y + nz[f] * a.Z;
    beyond |= (nd > g * (upper * pos[f] - na)) | (-nd > g * (upper * neg[f] + na));
  }
  return beyond != 0;
}

}  // namespace

NaturalSolver::NaturalSolver(std::span<const Xyz> columns, double step_nm, double natural_depth)
    : columns_(columns.begin(), columns.end()), step_nm_(step_nm), natural_depth_(natural_depth) {
  for (const Xyz& c : columns_) white_ = white_ + c;
  double scale = std::max(white_.max_abs(), 1e-300);
  const double tol = 1e-12 * scale;
  // Every facet of a zonotope or cone with 3D generators is spanned by two of them.
  for (std::size_t i = 0; i < columns_.size(); ++i)
    for (std::size_t j = i + 1; j < columns_.size(); ++j) {
      Xyz nrm = cross(columns_[i], columns_[j]);
      const double len = std::sqrt(dot(nrm, nrm));
      if (!(len > 1e-300)) continue;  // parallel generators span no facet
      nrm = (1.0 / len) * nrm;
      double pos = 0, neg = 0;
      for (const Xyz& c : columns_) {
        const double d = dot(nrm, c);
        (d > 0 ? pos : neg) += d;
      }
      solid_nx_.push_back(nrm.X);
      solid_ny_.push_back(nrm.Y);
      solid_nz_.push_back(nrm.Z);
      solid_pos_.push_back(pos);
      solid_neg_.push_back(-neg);
      // A facet of the cone: every generator on one side; the outward normal points away.
      if (-neg <= tol)
        cone_normals_.push_back(Xyz{} - nrm);
      else if (pos <= tol)
        cone_normals_.push_back(nrm);
    }
}

double NaturalSolver::depth(const Xyz& target, double upper) const {
  const bool light = !std::isfinite(upper);
  const double p = target.Y / (light ? white_.Y : upper * white_.Y);
  if (!(p > 0) || (!light && !(p < 1))) return INFINITY;
  // The grey (white, for lights) of the same luminance, and the ray from it to the target.
  const Xyz a = (light ? p : p * upper) * white_;
  const Xyz d = target - a;
  double depth = 0;
  if (light) {
    for (const Xyz& nrm : cone_normals_) {
      const double nd = dot(nrm, d);
      if (nd > 0) depth = std::max(depth, nd / -dot(nrm, a));
    }
    return depth;
  }
  return max_facet_ratio(solid_nx_.data(), solid_ny_.data(), solid_nz_.data(), solid_pos_.data(),
                         solid_neg_.data(), solid_pos_.size(), d, a, upper);
}

double NaturalSolver::roughness(std::span<const double> x, double upper) const {
  const bool light = !std::isfinite(upper);
  double sum = 0, prev = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(x[i] > 0) || (!light && !(x[i] < upper))) return INFINITY;
    const double z = light ? std::log(x[i]) : 0.5 * std::log(x[i] / (upper - x[i]));
    if (i > 0) sum += (z - prev) * (z - prev);
    prev = z;
  }
  return sum / step_nm_;
}

NaturalSpectrum NaturalSolver::solve(const Xyz& target, double upper) const {
  const std::size_t n = columns_.size();
  NaturalSpectrum out;
  out.values.assign(n, 0.0);
  if (!target.finite() || n < 3 || !(upper > 0)) return out;
  const bool light = !std::isfinite(upper);
  // White (reflectance: x == upper) is a vertex of the solid, flat and exact.
  if (!light && relative_error(target, upper * white_) <= kExact) {
    out.values.assign(n, upper);
    out.converged = true;
    return out;
  }
  const double p = target.Y / (light ? white_.Y : upper * white_.Y);
  if (!(p > 0) || (!light && !(p < 1))) return out;  // black, negative or brighter than white
  // The natural zone: solve for the target itself; deeper, for the target pulled back along
  // the ray from the grey to depth natural_depth_ (then projected exactly, below). Inside the
  // zone only the cheap test runs; the exact depth only beyond it.
  const Xyz a = (light ? p : p * upper) * white_;
  Xyz natural_target = target;
  const bool deep = light ? depth(target, upper) > natural_depth_
                          : deeper_than(solid_nx_.data(), solid_ny_.data(), solid_nz_.data(),
                                        solid_pos_.data(), solid_neg_.data(), solid_pos_.size(),
                                        target - a, a, upper, natural_depth_);
  if (deep) {
    const double g = depth(target, upper);
    if (!std::isfinite(g)) return out;
    if (g > natural_depth_) {
      out.fallback = true;
      out.fallback_weight = std::min(1.0, (g - natural_depth_) / (1.0 - natural_depth_));
      natural_target = a + (natural_depth_ / g) * (target - a);
    }
  }
  // Start at the flat spectrum of the same luminance (the exact solution on the grey ray).
  std::vector<double> z(n, grey_link(p, upper));
  const bool newton_ok = natural_newton(columns_, natural_target, upper, z, out.iterations);
  // Exact and bounded: the projection in the link's geometry onto the spectra of the target.
  // For a converged natural spectrum inside the zone it only removes the last rounding
  // (~1e-16); beyond the zone it is the continuous fallback.
  bool exact = link_projection(columns_, z, target, upper, out.iterations);
  for (std::size_t i = 0; i < n; ++i) out.values[i] = link(z[i], upper).x;
  if (!exact) {
    // Finish from the link projection's best point by least squares, first with the dual
    // Newton undamped (needed near the red end of the locus, where zbar vanishes), then damped
    // (needed for some violets, where the undamped steps wander); keep the closest result.
    auto error = [&](const std::vector<double>& x) {
      Xyz got;
      for (std::size_t i = 0; i < n; ++i) got = got + x[i] * columns_[i];
      return relative_error(got, target);
    };
    // The bounded projection (docs/DESIGN.md §5): the closest spectrum to the link's best
    // point with W x = t and 0 <= x <= upper, continuous in both and the identity on exact
    // bounded spectra.
    const std::vector<double> start = out.values;
    for (double damping : {kDualDamping, kSafetyDamping}) {
      const Projection p =
          project_exact(columns_, start, target, upper, {kExact, damping, kProjectionIterations});
      out.iterations += p.iterations;
      exact = p.residual <= kAccept;
      if (exact || error(p.values) < error(out.values)) out.values = p.values;
      if (exact) break;
    }
    out.safety_net = true;
  }
  // The contract, checked on the spectrum returned.
  Xyz got;
  for (std::size_t i = 0; i < n; ++i) got = got + out.values[i] * columns_[i];
  out.converged = newton_ok && relative_error(got, target) <= kAccept;
  return out;
}

}  // namespace spectralize
