#include "core/solvers/smooth_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/solvers/bounded_projection.h"

namespace spectralize {

namespace {

enum State : unsigned char { kFree = 0, kLower = 1, kUpper = 2 };

// Relative size of the ridge that makes H positive definite (first differences: constants,
// second: linear functions are its null space). Small enough not to bias the spectrum (tested:
// white stays flat to 1e-9), large enough to keep the banded factorisation well conditioned.
constexpr double kRidge = 1e-10;
// Primal-dual phase: iterations before the primal fallback takes over (it converges in a few
// for nearly all colours; cycling is possible because H is not an M-matrix).
constexpr int kPrimalDualIterations = 40;
static_assert(SmoothSolver::max_iterations(0) ==
                  kPrimalDualIterations + ProjectionControl{}.max_iterations + 50,
              "the stated cap is the loops' caps");

// Scratch of one reduced solve, reused across iterations.
struct Workspace {
  std::vector<int> free;                 // indices of the free samples
  std::vector<double> d, l1, l2;         // banded LDL^T factor of H_FF
  std::vector<std::array<double, 4>> y;  // H_FF^-1 [r, c_X, c_Y, c_Z] on the free set
};

}  // namespace

SmoothSolver::SmoothSolver(std::span<const Xyz> columns, Roughness roughness)
    : columns_(columns.begin(), columns.end()) {
  const std::size_t n = columns_.size();
  h0_.assign(n, 0);
  h1_.assign(n, 0);
  h2_.assign(n, 0);
  // H = a D1^T D1 + b D2^T D2 for the difference operators, accumulated row by row.
  const double a = roughness.slope, b = roughness.curvature;
  for (std::size_t i = 0; i + 1 < n; ++i) {  // row (x_{i+1} - x_i)
    h0_[i] += a;
    h0_[i + 1] += a;
    h1_[i] -= a;
  }
  band_ = b > 0 ? 2 : 1;
  for (std::size_t i = 0; b > 0 && i + 2 < n; ++i) {  // row (x_i - 2 x_{i+1} + x_{i+2})
    h0_[i] += b;
    h0_[i + 1] += 4 * b;
    h0_[i + 2] += b;
    h1_[i] -= 2 * b;
    h1_[i + 1] -= 2 * b;
    h2_[i] += b;
  }
  ridge_ = kRidge * *std::max_element(h0_.begin(), h0_.end());
}

double SmoothSolver::roughness(std::span<const double> x) const {
  double sum = 0;
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i) {
    double hx = h0_[i] * x[i];
    if (i + 1 < n) hx += h1_[i] * x[i + 1];
    if (i >= 1) hx += h1_[i - 1] * x[i - 1];
    if (i + 2 < n) hx += h2_[i] * x[i + 2];
    if (i >= 2) hx += h2_[i - 2] * x[i - 2];
    sum += x[i] * hx;
  }
  return sum;
}

namespace {

// Why the banded factorisation is written here: Eigen has no banded solver, and its sparse
// SimplicialLDLT (natural ordering) took 10 us per reduced system at 5 nm (assembly, factor,
// 4 solves), against ~2 us here; with ~6 systems per colour that alone would exceed the 50 us
// budget. Eigen does the 3x3 Schur complement.
//
// One equality-constrained solve for a fixed active set: the samples in L are 0, those in U
// are `upper`, the free ones minimise x^T H x subject to W x = target. By the Schur complement
// on the 3 multipliers: x_F = y0 - Y nu, with H_FF y0 = r, H_FF Y = W_F^T, S nu = W_F y0 - b.
// Returns false when fewer than 3 samples are free or W_F is rank-deficient.
struct ReducedSystem {
  std::span<const Xyz> c;
  const std::vector<double>& h0;
  const std::vector<double>& h1;
  const std::vector<double>& h2;
  double ridge;
  int band;

  // H_ij for |i - j| <= 2.
  double h(int i, int j) const {
    if (i > j) std::swap(i, j);
    switch (j - i) {
      case 0:
        return h0[i] + ridge;
      case 1:
        return h1[i];
      case 2:
        return h2[i];
      default:
        return 0;
    }
  }

  // `centre`: the ridge pulls toward it (proximal point), not toward 0, so that re-solving with
  // the previous solution as centre removes the ridge's bias; empty means 0.
  bool solve(const std::vector<unsigned char>& state, double upper, const Xyz& target,
             Workspace& ws, std::vector<double>& x, Xyz& nu,
             std::span<const double> centre = {}) const {
    const int n = static_cast<int>(c.size());
    ws.free.clear();
    Xyz b = target;
    for (int i = 0; i < n; ++i) {
      if (state[i] == kFree)
        ws.free.push_back(i);
      else if (state[i] == kUpper)
        b = b - upper * c[i];
    }
    const int m = static_cast<int>(ws.free.size());
    if (m < 3) return false;
    ws.d.resize(m);
    ws.l1.resize(m);
    ws.l2.resize(m);
    ws.y.resize(m);
    const std::vector<int>& f = ws.free;
    // Banded LDL^T of H_FF (a principal submatrix of a banded matrix is banded, same width).
    // Entries between free samples more than `band` apart are 0.
    auto coupling = [&](int k, int gap) {  // H between free samples k and k + gap
      return k + gap < m && f[k + gap] - f[k] <= band ? h(f[k], f[k + gap]) : 0.0;
    };
    for (int k = 0; k < m; ++k) {
      double dk = h0[f[k]] + ridge;
      double e1 = coupling(k, 1);
      if (k >= 1) {
        dk -= ws.l1[k - 1] * ws.l1[k - 1] * ws.d[k - 1];
        e1 -= ws.l2[k - 1] * ws.l1[k - 1] * ws.d[k - 1];
      }
      if (k >= 2) dk -= ws.l2[k - 2] * ws.l2[k - 2] * ws.d[k - 2];
      if (!(dk > 0)) return false;
      ws.d[k] = dk;
      ws.l1[k] = e1 / dk;
      ws.l2[k] = coupling(k, 2) / dk;
    }
    // Right-hand sides: r = -H_FU x_U + ridge centre (the lower bounds are 0), and the three
    // weight rows.
    for (int k = 0; k < m; ++k) {
      const int i = f[k];
      double r = centre.empty() ? 0.0 : ridge * centre[i];
      if (upper != 0 && upper != INFINITY)
        for (int j = std::max(0, i - band); j <= std::min(n - 1, i + band); ++j)
          if (state[j] == kUpper) r -= h(i, j) * upper;
      ws.y[k] = {r, c[i].X, c[i].Y, c[i].Z};
    }
    // Forward, diagonal and backward substitution for the four columns at once (l1, l2 of the
    // last two rows are 0, so the recurrences need no bounds tests past the first two rows).
    auto axpy = [](std::array<double, 4>& y, double a, const std::array<double, 4>& x) {
      for (int q = 0; q < 4; ++q) y[q] -= a * x[q];
    };
    if (m >= 2) axpy(ws.y[1], ws.l1[0], ws.y[0]);
    for (int k = 2; k < m; ++k) {
      axpy(ws.y[k], ws.l1[k - 1], ws.y[k - 1]);
      axpy(ws.y[k], ws.l2[k - 2], ws.y[k - 2]);
    }
    for (int k = 0; k < m; ++k)
      for (int q = 0; q < 4; ++q) ws.y[k][q] /= ws.d[k];
    axpy(ws.y[m - 2], ws.l1[m - 2], ws.y[m - 1]);
    for (int k = m - 3; k >= 0; --k) {
      axpy(ws.y[k], ws.l1[k], ws.y[k + 1]);
      axpy(ws.y[k], ws.l2[k], ws.y[k + 2]);
    }
    // The 3x3 Schur complement S = W_F H_FF^-1 W_F^T (symmetric positive definite when W_F has
    // full rank).
    double acc[3][4] = {};  // rows: c_X, c_Y, c_Z; columns: y0, Y_X, Y_Y, Y_Z
    for (int k = 0; k < m; ++k) {
      const Xyz& ck = c[f[k]];
      for (int q = 0; q < 4; ++q) {
        acc[0][q] += ck.X * ws.y[k][q];
        acc[1][q] += ck.Y * ws.y[k][q];
        acc[2][q] += ck.Z * ws.y[k][q];
      }
    }
    Eigen::Matrix3d s;
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) s(p, q) = 0.5 * (acc[p][q + 1] + acc[q][p + 1]);
    const Eigen::Vector3d rhs(acc[0][0] - b.X, acc[1][0] - b.Y, acc[2][0] - b.Z);
    Eigen::LDLT<Eigen::Matrix3d> ldlt(s);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    const Eigen::Vector3d v = ldlt.solve(rhs);
    if (!v.allFinite()) return false;
    nu = {v[0], v[1], v[2]};
    for (int i = 0; i < n; ++i) x[i] = state[i] == kUpper ? upper : 0.0;
    for (int k = 0; k < m; ++k)
      x[f[k]] = ws.y[k][0] - (ws.y[k][1] * v[0] + ws.y[k][2] * v[1] + ws.y[k][3] * v[2]);
    // Refinement of the equality constraints (the Schur solve loses digits when H_FF is nearly
    // singular): the correction Y S^-1 residual keeps H x + W^T nu = 0 on the free set.
    for (int pass = 0; pass < 2; ++pass) {
      Xyz residual = target;
      for (int i = 0; i < n; ++i) residual = residual - x[i] * c[i];
      const Eigen::Vector3d a = ldlt.solve(Eigen::Vector3d(residual.X, residual.Y, residual.Z));
      if (!a.allFinite()) break;
      for (int k = 0; k < m; ++k)
        x[f[k]] += ws.y[k][1] * a[0] + ws.y[k][2] * a[1] + ws.y[k][3] * a[2];
      nu = nu - Xyz{a[0], a[1], a[2]};
    }
    return true;
  }

  // g = H x + W^T nu: the bound multipliers (>= 0 at a lower bound, <= 0 at an upper bound).
  double gradient(const std::vector<double>& x, const Xyz& nu, int i) const {
    const int n = static_cast<int>(c.size());
    double g = dot(c[i], nu);
    for (int j = std::max(0, i - band); j <= std::min(n - 1, i + band); ++j) g += h(i, j) * x[j];
    return g;
  }
};

}  // namespace

SmoothSpectrum SmoothSolver::solve(const Xyz& target, double upper,
                                   std::span<const double> feasible) const {
  const int n = static_cast<int>(columns_.size());
  SmoothSpectrum out;
  out.values.assign(n, 0.0);
  const ReducedSystem sys{columns_, h0_, h1_, h2_, ridge_, band_};
  Workspace ws;
  std::vector<unsigned char> state(n, kFree), next(n);
  std::vector<double>& x = out.values;
  Xyz nu;
  // Tolerances: bounds are met to 1e-12 of the spectrum's scale before the final clamp;
  // multipliers are compared with the scale of H x.
  double scale = 0;

  // Phase 1: primal-dual active set (semismooth Newton on the complementarity conditions),
  // starting from the solution without bounds. Converges in a handful of iterations when it
  // does; an active set seen twice means a cycle.
  const double c_pd = 1.0 / (*std::max_element(h0_.begin(), h0_.end()));
  std::vector<std::vector<unsigned char>> seen;
  bool ok = false;
  for (int it = 0; it < kPrimalDualIterations; ++it) {
    ++out.iterations;
    const std::vector<double> centre = x;  // the previous iterate (0 at first)
    if (!sys.solve(state, upper, target, ws, x, nu, centre)) break;
    if (it == 0) {
      for (double v : x) scale = std::max(scale, std::abs(v));
      scale = std::max(scale, 1e-300);
    }
    const double tol = 1e-12 * scale;
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      const double g = state[i] == kFree ? 0.0 : sys.gradient(x, nu, i);
      const double probe = x[i] - c_pd * g;
      unsigned char s = kFree;
      if (probe < -tol)
        s = kLower;
      else if (probe > upper + tol)
        s = kUpper;
      else if (state[i] != kFree && std::abs(g) * c_pd <= tol)
        s = state[i];  // degenerate: on the bound with a zero multiplier; keep it
      next[i] = s;
      changed |= s != state[i];
    }
    if (!changed) {
      // The active set is final: one proximal re-solve centred on x removes most of what is
      // left of the ridge's bias (it shrinks by ridge / smallest curvature, < 1e-4). A failed
      // solve leaves x as it was.
      const std::vector<double> last = x;
      sys.solve(state, upper, target, ws, x, nu, last);
      ok = true;
      break;
    }
    if (std::find(seen.begin(), seen.end(), next) != seen.end()) break;  // cycling
    seen.push_back(state);
    state.swap(next);
  }

  // Phase 2 (rare): the primal active-set method from a feasible spectrum. Each step keeps W x
  // = target and the bounds and lowers x^T H x, so it stops after finitely many steps; capped.
  if (!ok) {
    out.fallback = true;
    std::vector<double> start;
    if (feasible.size() == static_cast<std::size_t>(n)) {
      start.assign(feasible.begin(), feasible.end());
    } else {
      std::vector<double> guess(n);
      for (int i = 0; i < n; ++i) guess[i] = std::clamp(x[i], 0.0, upper);
      Projection p = project_exact(columns_, guess, target, upper);
      out.iterations += p.iterations;
      if (!p.converged) {  // infeasible target: the bounded best effort
        for (double& v : x) v = std::clamp(v, 0.0, upper);
        return out;
      }
      start = std::move(p.values);
    }
    x = start;
    if (scale == 0) {
      for (double v : x) scale = std::max(scale, std::abs(v));
      scale = std::max(scale, 1e-300);
    }
    const double tol = 1e-12 * scale;
    for (int i = 0; i < n; ++i)
      state[i] = x[i] <= tol ? kLower : (x[i] >= upper - tol ? kUpper : kFree);
    std::vector<double> candidate(n);
    Xyz cand_nu;
    for (int it = 0; it < 4 * n + 50; ++it) {
      ++out.iterations;
      if (!sys.solve(state, upper, target, ws, candidate, cand_nu, x)) {
        // Too few free samples to meet the 3 constraints: free the first bound sample and
        // retry (at most n times in all, within the cap).
        int best = -1;
        for (int i = 0; i < n && best < 0; ++i)
          if (state[i] != kFree) best = i;
        if (best < 0) break;
        state[best] = kFree;
        continue;
      }
      // Step toward the candidate as far as the bounds allow.
      double alpha = 1;
      int blocking = -1;
      bool blocking_upper = false;
      for (int i = 0; i < n; ++i) {
        if (state[i] != kFree) continue;
        const double p = candidate[i] - x[i];
        if (p < 0 && x[i] + alpha * p < 0) {
          alpha = std::max(0.0, -x[i] / p);
          blocking = i;
          blocking_upper = false;
        } else if (p > 0 && x[i] + alpha * p > upper) {
          alpha = std::max(0.0, (upper - x[i]) / p);
          blocking = i;
          blocking_upper = true;
        }
      }
      for (int i = 0; i < n; ++i)
        if (state[i] == kFree) x[i] += alpha * (candidate[i] - x[i]);
      if (blocking >= 0) {
        state[blocking] = blocking_upper ? kUpper : kLower;
        x[blocking] = blocking_upper ? upper : 0.0;
        continue;
      }
      // At the candidate: optimal if every bound multiplier has the right sign, else release
      // the most wrong one.
      nu = cand_nu;
      int worst = -1;
      double worst_value = tol * (1.0 / c_pd);
      for (int i = 0; i < n; ++i) {
        if (state[i] == kFree) continue;
        const double g = sys.gradient(x, nu, i);
        const double wrong = state[i] == kLower ? -g : g;
        if (wrong > worst_value) {
          worst_value = wrong;
          worst = i;
        }
      }
      if (worst < 0) {
        ok = true;
        break;
      }
      state[worst] = kFree;
    }
  }
  for (double& v : x) v = std::clamp(v, 0.0, upper);
  out.converged = ok;
  return out;
}

}  // namespace spectralize
