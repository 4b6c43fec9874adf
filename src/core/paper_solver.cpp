#include "core/paper_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <numeric>

namespace spectralize {

namespace {

// Per-thread working memory, so solve() allocates nothing in steady state.
struct Scratch {
  std::vector<std::size_t> order;
  std::vector<double> angle, ux, uy, scale, cross, acc;
  std::vector<std::uint32_t> upper;
  std::vector<float> max_density;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// The geometry of one target: samples sorted by angle around it, their pairwise cross
// products (twice the signed triangle areas seen from the target) and the density scales.
struct Fan {
  std::size_t m = 0;
  const double* angle;
  const double* cross;  // cross[p*m + q] = u_p x u_q
  const double* scale;  // S / s_p: barycentric coordinate -> density
  const std::uint32_t* upper;  // first r with angle[r] >= angle[q] + pi
};

// Visits every admissible triple (p < q < r in angular order) as one call per (p, q) with the
// contiguous range [r0, r1) of third vertices. A triangle contains the target iff no angular
// gap between its vertices reaches pi.
template <typename RowFn>
void for_each_admissible_row(const Fan& f, RowFn&& row) {
  constexpr double pi = std::numbers::pi;
  std::size_t lo = 0;
  for (std::size_t p = 0; p + 2 < f.m; ++p) {
    // Third vertices must lie strictly beyond angle[p] + pi.
    if (lo < p + 1) lo = p + 1;
    while (lo < f.m && f.angle[lo] <= f.angle[p] + pi) ++lo;
    if (lo >= f.m) break;
    for (std::size_t q = p + 1; q < f.m && f.angle[q] - f.angle[p] < pi; ++q) {
      std::size_t r0 = std::max(lo, q + 1), r1 = f.upper[q];
      if (r0 < r1) row(p, q, r0, r1);
    }
  }
}

// One row of triples (p, q, r in [r0, r1)): barycentric coordinates from the cross table.
// Adds the r densities into acc and returns the p and q sums. Vectorised over r.
inline void accumulate_row(const Fan& f, std::size_t p, std::size_t q, std::size_t r0,
                           std::size_t r1, double* acc) {
  const double* cp = f.cross + p * f.m;
  const double* cq = f.cross + q * f.m;
  const double* sc = f.scale;
  const double apq = cp[q];
  double sp = 0, sq = 0;
#pragma omp simd reduction(+ : sp, sq)
  for (std::size_t r = r0; r < r1; ++r) {
    double aqr = cq[r], arp = -cp[r];
    double inv = 1.0 / (apq + aqr + arp);
    sp += aqr * inv;
    sq += arp * inv;
    acc[r] += apq * inv * sc[r];
  }
  acc[p] += sp * sc[p];
  acc[q] += sq * sc[q];
}

// Records the largest density of each triple of the row, in visiting order.
inline void max_density_row(const Fan& f, std::size_t p, std::size_t q, std::size_t r0,
                            std::size_t r1, float* out) {
  const double* cp = f.cross + p * f.m;
  const double* cq = f.cross + q * f.m;
  const double* sc = f.scale;
  const double apq = cp[q], sp = sc[p], sq = sc[q];
#pragma omp simd
  for (std::size_t r = r0; r < r1; ++r) {
    double aqr = cq[r], arp = -cp[r];
    double inv = 1.0 / (apq + aqr + arp);
    double d = std::max(std::max(aqr * inv * sp, arp * inv * sq), apq * inv * sc[r]);
    out[r - r0] = static_cast<float>(std::max(d, 0.0));
  }
}

// Like accumulate_row, but only for triples whose recorded largest density is <= cut.
inline std::size_t accumulate_row_below(const Fan& f, std::size_t p, std::size_t q,
                                        std::size_t r0, std::size_t r1, const float* md,
                                        float cut, double* acc) {
  const double* cp = f.cross + p * f.m;
  const double* cq = f.cross + q * f.m;
  const double* sc = f.scale;
  const double apq = cp[q];
  double sp = 0, sq = 0;
  std::size_t kept = 0;
#pragma omp simd reduction(+ : sp, sq, kept)
  for (std::size_t r = r0; r < r1; ++r) {
    double keep = md[r - r0] <= cut ? 1.0 : 0.0;
    double aqr = cq[r], arp = -cp[r];
    double inv = keep / (apq + aqr + arp);
    sp += aqr * inv;
    sq += arp * inv;
    acc[r] += apq * inv * sc[r];
    kept += md[r - r0] <= cut ? 1 : 0;
  }
  acc[p] += sp * sc[p];
  acc[q] += sq * sc[q];
  return kept;
}

// The k-th smallest (0-based) of non-negative floats, by radix selection on their bit
// patterns (which order like the values): three histogram passes, O(n).
float select_kth(std::span<const float> v, std::size_t k) {
  std::uint32_t prefix = 0, mask = 0;
  const int shifts[3] = {21, 10, 0};
  const int widths[3] = {11, 11, 10};
  std::vector<std::uint32_t> hist(2048);
  for (int pass = 0; pass < 3; ++pass) {
    std::fill(hist.begin(), hist.end(), 0);
    const std::uint32_t wmask = (1u << widths[pass]) - 1;
    for (float x : v) {
      std::uint32_t b;
      std::memcpy(&b, &x, sizeof b);
      if ((b & mask) == prefix) ++hist[(b >> shifts[pass]) & wmask];
    }
    std::uint32_t j = 0;
    while (k >= hist[j]) k -= hist[j++];
    prefix |= j << shifts[pass];
    mask |= wmask << shifts[pass];
  }
  float out;
  std::memcpy(&out, &prefix, sizeof out);
  return out;
}

}  // namespace

PaperSolver::PaperSolver(std::span<const Xyz> weights) : n_(weights.size()) {
  for (std::size_t i = 0; i < weights.size(); ++i) {
    double s = weights[i].sum();
    if (!(s > 0)) continue;  // a sample the eye (or the illuminant) does not see
    active_.push_back(i);
    chroma_x_.push_back(weights[i].X / s);
    chroma_y_.push_back(weights[i].Y / s);
    weight_sum_.push_back(s);
  }
}

// Builds the fan of the samples around the target's chromaticity into the scratch.
static Fan make_fan(const std::vector<double>& cx, const std::vector<double>& cy,
                    const std::vector<double>& ws, const Xyz& target, Scratch& s) {
  Fan f;
  const std::size_t m = cx.size();
  const double S = target.sum();
  const double xt = target.X / S, yt = target.Y / S;
  s.order.resize(m);
  s.angle.resize(m);
  s.ux.resize(m);
  s.uy.resize(m);
  s.scale.resize(m);
  s.cross.resize(m * m);
  s.upper.resize(m);
  std::vector<double>& raw = s.acc;  // borrowed as temporary angle storage
  raw.resize(m);
  for (std::size_t i = 0; i < m; ++i) raw[i] = std::atan2(cy[i] - yt, cx[i] - xt);
  std::iota(s.order.begin(), s.order.end(), std::size_t{0});
  std::sort(s.order.begin(), s.order.end(),
            [&](std::size_t a, std::size_t b) { return raw[a] < raw[b] || (raw[a] == raw[b] && a < b); });
  for (std::size_t p = 0; p < m; ++p) {
    std::size_t i = s.order[p];
    s.angle[p] = raw[i];
    s.ux[p] = cx[i] - xt;
    s.uy[p] = cy[i] - yt;
    s.scale[p] = S / ws[i];
  }
  for (std::size_t p = 0; p < m; ++p)
    for (std::size_t q = 0; q < m; ++q) s.cross[p * m + q] = s.ux[p] * s.uy[q] - s.uy[p] * s.ux[q];
  // upper[q]: first index r whose angle reaches angle[q] + pi (monotone in q).
  std::size_t r = 0;
  for (std::size_t q = 0; q < m; ++q) {
    if (r < q) r = q;
    while (r < m && s.angle[r] < s.angle[q] + std::numbers::pi) ++r;
    s.upper[q] = static_cast<std::uint32_t>(r);
  }
  f.m = m;
  f.angle = s.angle.data();
  f.cross = s.cross.data();
  f.scale = s.scale.data();
  f.upper = s.upper.data();
  return f;
}

std::size_t PaperSolver::sum_admissible(const Xyz& target, std::span<double> sum) const {
  std::fill(sum.begin(), sum.end(), 0.0);
  if (!(target.sum() > 0) || active_.size() < 3) return 0;
  Scratch& s = scratch();
  Fan f = make_fan(chroma_x_, chroma_y_, weight_sum_, target, s);
  s.acc.assign(f.m, 0.0);
  std::size_t count = 0;
  for_each_admissible_row(f, [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
    accumulate_row(f, p, q, r0, r1, s.acc.data());
    count += r1 - r0;
  });
  for (std::size_t p = 0; p < f.m; ++p) sum[active_[s.order[p]]] = s.acc[p];
  return count;
}

PaperSpectrum PaperSolver::solve(const Xyz& target, const EdgeFilter& filter) const {
  PaperSpectrum out;
  out.values.assign(n_, 0.0);
  if (filter.value() == 0) {
    out.admissible = sum_admissible(target, out.values);
  } else if (target.sum() > 0 && active_.size() >= 3) {
    Scratch& s = scratch();
    Fan f = make_fan(chroma_x_, chroma_y_, weight_sum_, target, s);
    // Pass 1: the largest density of every admissible triple, in visiting order.
    s.max_density.clear();
    for_each_admissible_row(f, [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
      std::size_t at = s.max_density.size();
      s.max_density.resize(at + (r1 - r0));
      max_density_row(f, p, q, r0, r1, s.max_density.data() + at);
    });
    out.admissible = s.max_density.size();
    if (out.admissible > 0) {
      // Keep the L - K smallest; ties at the cut are all kept.
      std::size_t keep = out.admissible - filter.drop_count(out.admissible);
      float cut = select_kth(s.max_density, keep - 1);
      // Pass 2: sum the kept triples.
      s.acc.assign(f.m, 0.0);
      std::size_t at = 0, kept = 0;
      for_each_admissible_row(f, [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
        kept += accumulate_row_below(f, p, q, r0, r1, s.max_density.data() + at, cut, s.acc.data());
        at += r1 - r0;
      });
      out.dropped = out.admissible - kept;
      for (std::size_t p = 0; p < f.m; ++p) out.values[active_[s.order[p]]] = s.acc[p];
    }
  }
  std::size_t used = out.admissible - out.dropped;
  if (used > 0)
    for (double& v : out.values) v /= static_cast<double>(used);
  return out;
}

}  // namespace spectralize
