#include "core/solvers/paper_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <numeric>

#include "core/multiversion.h"

namespace spectralize {

namespace {

// An allocator that leaves new floats uninitialised: the max-density buffer grows row by row
// and every element is written right after, so zero-filling it would be wasted bandwidth.
template <typename T>
struct UninitialisedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <typename U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) {}
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
using FloatBuffer = std::vector<float, UninitialisedAllocator<float>>;

// Half a turn of the pseudo-angle used to sort the samples around the target.
constexpr double kHalfTurn = 2.0;

// Per-thread working memory, so solve() allocates nothing in steady state.
// The triple kernels run in float (twice the SIMD lanes); the angular decisions that select the
// admissible triples are made in double, and the final exact projection restores double precision.
using Real = float;

struct Scratch {
  std::vector<std::size_t> order;
  std::vector<double> angle, ux, uy, acc;
  std::vector<Real> scale, cross;
  std::vector<std::uint32_t> upper;
  FloatBuffer max_density;
  std::vector<float> bucket;  // candidates for the cut, see CutFinder
  std::vector<std::uint32_t> histogram;
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
  const Real* cross;           // cross[p*m + q] = u_p x u_q
  const Real* scale;           // S / s_p: barycentric coordinate -> density
  const std::uint32_t* upper;  // first r with angle[r] >= angle[q] + pi
};

// Visits every admissible triple (p < q < r in angular order) as one call per (p, q) with the
// contiguous range [r0, r1) of third vertices, and calls end_p(p) after each first vertex. A
// triangle contains the target iff no angular gap between its vertices reaches pi.
template <typename RowFn, typename EndFn>
[[gnu::always_inline]] inline void for_each_admissible_row(const Fan& f, RowFn&& row,
                                                           EndFn&& end_p) {
  constexpr double pi = kHalfTurn;
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
    end_p(p);
  }
}

// Lane-wise accumulators of barycentric coordinates, so the inner loops need no horizontal
// reductions: the p-coordinates go to a per-p row, the q-coordinates to row q of a matrix, the
// r-coordinates to their vertex directly; everything is summed and scaled once at the end.
struct Accumulators {
  std::vector<Real> r_sum, p_row, q_rows, p_sum;
  // finish() zeroes the q rows as it reads them, so only a change of size clears them here.
  void reset(std::size_t m) {
    r_sum.assign(m, 0);
    p_row.assign(m, 0);
    if (q_rows.size() != m * m) q_rows.assign(m * m, 0);
    p_sum.assign(m, 0);
  }
  // Only third vertices r > p (and r > q) are ever written, so the sums start there.
  [[gnu::always_inline]] void end_p(std::size_t p, std::size_t m) {
    Real sum = 0;
    Real* row = p_row.data();
#pragma omp simd reduction(+ : sum)
    for (std::size_t r = p + 1; r < m; ++r) sum += row[r];
    std::fill(row + p + 1, row + m, Real(0));
    p_sum[p] += sum;
  }
  // Density of vertex v: its scale times all its barycentric coordinates.
  [[gnu::always_inline]] void finish(const Fan& f, double* out) {
    for (std::size_t v = 0; v < f.m; ++v) {
      Real* row = q_rows.data() + v * f.m;
      Real q_total = 0;
#pragma omp simd reduction(+ : q_total)
      for (std::size_t r = v + 1; r < f.m; ++r) q_total += row[r];
      std::fill(row + v + 1, row + f.m, Real(0));
      double total = static_cast<double>(r_sum[v]) + static_cast<double>(p_sum[v]) +
                     static_cast<double>(q_total);
      out[v] = total * static_cast<double>(f.scale[v]);
    }
  }
};

// One row of triples (p, q, r in [r0, r1)): barycentric coordinates from the cross table,
// added to the accumulators. Filtered: only triples whose recorded largest density md[r - r0]
// is <= cut. Returns how many triples were added.
template <bool kFiltered>
[[gnu::always_inline]] inline std::size_t accumulate_row(const Fan& f, std::size_t p, std::size_t q,
                                                         std::size_t r0, std::size_t r1,
                                                         Accumulators& a, const float* md = nullptr,
                                                         float cut = 0) {
  const Real* cp = f.cross + p * f.m;
  const Real* cq = f.cross + q * f.m;
  Real* pr = a.p_row.data();
  Real* qr = a.q_rows.data() + q * f.m;
  Real* rs = a.r_sum.data();
  const Real apq = cp[q];
  // Triple (p, q, r) with weight keep (1 or 0): its three barycentric coordinates.
  auto add = [&](std::size_t r, Real keep) {
    Real aqr = cq[r], arp = -cp[r];
    Real inv = keep / (apq + aqr + arp);
    pr[r] += aqr * inv;
    qr[r] += arp * inv;
    rs[r] += apq * inv;
  };
  if constexpr (!kFiltered) {
#pragma omp simd
    for (std::size_t r = r0; r < r1; ++r) add(r, Real(1));
    return r1 - r0;
  } else {
    std::size_t kept = 0;
#pragma omp simd reduction(+ : kept)
    for (std::size_t r = r0; r < r1; ++r) {
      bool keep = md[r - r0] <= cut;
      add(r, keep ? Real(1) : Real(0));
      kept += keep ? 1 : 0;
    }
    return kept;
  }
}

// Records the largest density of each triple of the row, in visiting order.
[[gnu::always_inline]] inline void max_density_row(const Fan& f, std::size_t p, std::size_t q,
                                                   std::size_t r0, std::size_t r1, float* out) {
  const Real* cp = f.cross + p * f.m;
  const Real* cq = f.cross + q * f.m;
  const Real* sc = f.scale;
  const Real apq = cp[q], sp = sc[p], sq = sc[q];
#pragma omp simd
  for (std::size_t r = r0; r < r1; ++r) {
    Real aqr = cq[r], arp = -cp[r];
    Real inv = Real(1) / (apq + aqr + arp);
    Real a = aqr * inv * sp, b = arp * inv * sq, c = apq * inv * sc[r];
    Real d = a > b ? a : b;
    d = d > c ? d : c;
    out[r - r0] = d > 0 ? d : 0;
  }
}

// Finds k-th smallest values (0-based) of non-negative floats: one histogram pass over the top
// 12 bits of their bit patterns (which order like the values; 8 buckets per octave), then per
// query one pass gathering the k-th's bucket and nth_element on that small set.
class CutFinder {
 public:
  static constexpr int kShift = 20;
  CutFinder(std::span<const float> values, std::vector<std::uint32_t>& histogram,
            std::vector<float>& bucket)
      : values_(values), hist_(histogram), bucket_(bucket) {
    // Four interleaved histograms: neighbouring values often share a bucket, and one counter
    // incremented back to back would serialise on store-to-load forwarding.
    constexpr std::size_t buckets = std::size_t{1} << (32 - kShift);
    hist_.assign(4 * buckets, 0);
    const std::size_t n = values_.size(), n4 = n & ~std::size_t{3};
    for (std::size_t i = 0; i < n4; i += 4) {
      ++hist_[bits(values_[i]) >> kShift];
      ++hist_[buckets + (bits(values_[i + 1]) >> kShift)];
      ++hist_[2 * buckets + (bits(values_[i + 2]) >> kShift)];
      ++hist_[3 * buckets + (bits(values_[i + 3]) >> kShift)];
    }
    for (std::size_t i = n4; i < n; ++i) ++hist_[bits(values_[i]) >> kShift];
    for (std::size_t b = 0; b < buckets; ++b)
      hist_[b] += hist_[buckets + b] + hist_[2 * buckets + b] + hist_[3 * buckets + b];
  }
  float kth(std::size_t k) {
    std::uint32_t j = 0;
    while (k >= hist_[j]) k -= hist_[j++];
    // Branch-free gather of the bucket's members.
    bucket_.resize(values_.size() + 1);
    std::size_t count = 0;
    for (float x : values_) {
      bucket_[count] = x;
      count += (bits(x) >> kShift) == j;
    }
    std::nth_element(bucket_.begin(), bucket_.begin() + static_cast<std::ptrdiff_t>(k),
                     bucket_.begin() + static_cast<std::ptrdiff_t>(count));
    return bucket_[k];
  }

 private:
  static std::uint32_t bits(float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  }
  std::span<const float> values_;
  std::vector<std::uint32_t>& hist_;
  std::vector<float>& bucket_;
};

// The three passes over all admissible triples, compiled for AVX2 and baseline x86-64 (AVX-512
// measured slower: rows are short, ~10 triples)
// and picked at load time, so one binary is fast on any machine.
SPECTRALIZE_MULTIVERSION_AVX2
std::size_t sum_all(const Fan& f, Accumulators& a, double* out) {
  std::size_t count = 0;
  a.reset(f.m);
  for_each_admissible_row(
      f,
      [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
        count += accumulate_row<false>(f, p, q, r0, r1, a);
      },
      [&](std::size_t p) { a.end_p(p, f.m); });
  a.finish(f, out);
  return count;
}

SPECTRALIZE_MULTIVERSION_AVX2
void record_max_densities(const Fan& f, FloatBuffer& out) {
  out.clear();
  for_each_admissible_row(
      f,
      [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
        std::size_t at = out.size();
        out.resize(at + (r1 - r0));
        max_density_row(f, p, q, r0, r1, out.data() + at);
      },
      [](std::size_t) {});
}

SPECTRALIZE_MULTIVERSION_AVX2
std::size_t sum_below(const Fan& f, const float* md, float cut, Accumulators& a, double* out) {
  std::size_t at = 0, kept = 0;
  a.reset(f.m);
  for_each_admissible_row(
      f,
      [&](std::size_t p, std::size_t q, std::size_t r0, std::size_t r1) {
        kept += accumulate_row<true>(f, p, q, r0, r1, a, md + at, cut);
        at += r1 - r0;
      },
      [&](std::size_t p) { a.end_p(p, f.m); });
  a.finish(f, out);
  return kept;
}

}  // namespace

PaperSolver::PaperSolver(std::span<const Xyz> weights, std::span<const double> wavelengths)
    : bands_(wavelengths), n_(weights.size()) {
  for (std::size_t i = 0; i < weights.size(); ++i) {
    double s = weights[i].sum();
    if (!(s > 0)) continue;  // a sample the eye (or the illuminant) does not see
    active_.push_back(i);
    chroma_x_.push_back(weights[i].X / s);
    chroma_y_.push_back(weights[i].Y / s);
    weight_sum_.push_back(s);
  }
}

// A pseudo-angle in [0, 4) of the direction (x, y): strictly increasing with the true angle,
// and the opposite direction is exactly 2 further (mod 4), which is all the fan needs ("half a
// turn" is 2). Much cheaper than atan2.
static double diamond_angle(double x, double y) {
  double l1 = std::abs(x) + std::abs(y);
  if (l1 == 0) return 0;
  if (y >= 0) return x >= 0 ? y / l1 : 1 - x / l1;
  return x < 0 ? 2 - y / l1 : 3 + x / l1;
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
  for (std::size_t i = 0; i < m; ++i) raw[i] = diamond_angle(cx[i] - xt, cy[i] - yt);
  std::iota(s.order.begin(), s.order.end(), std::size_t{0});
  std::sort(s.order.begin(), s.order.end(), [&](std::size_t a, std::size_t b) {
    return raw[a] < raw[b] || (raw[a] == raw[b] && a < b);
  });
  for (std::size_t p = 0; p < m; ++p) {
    std::size_t i = s.order[p];
    s.angle[p] = raw[i];
    s.ux[p] = cx[i] - xt;
    s.uy[p] = cy[i] - yt;
    s.scale[p] = static_cast<Real>(1.0 / ws[i]);  // densities for X+Y+Z = 1; times S later
  }
  for (std::size_t p = 0; p < m; ++p)
    for (std::size_t q = 0; q < m; ++q)
      s.cross[p * m + q] = static_cast<Real>(s.ux[p] * s.uy[q] - s.uy[p] * s.ux[q]);
  // upper[q]: first index r whose angle reaches angle[q] + pi (monotone in q).
  std::size_t r = 0;
  for (std::size_t q = 0; q < m; ++q) {
    if (r < q) r = q;
    while (r < m && s.angle[r] < s.angle[q] + kHalfTurn) ++r;
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
  thread_local Accumulators acc;
  s.acc.resize(f.m);
  std::size_t count = sum_all(f, acc, s.acc.data());
  // The fan works on the colour scaled to X+Y+Z = 1 (so float never over- or underflows, and
  // the result scales exactly); scale back in double.
  const double S = target.sum();
  for (std::size_t p = 0; p < f.m; ++p) sum[active_[s.order[p]]] = S * s.acc[p];
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
    record_max_densities(f, s.max_density);
    out.admissible = s.max_density.size();
    // Fractions to try: one, or the automatic ladder until no edge peak is left.
    std::vector<double> steps;
    if (filter.kind() == EdgeFilter::Kind::automatic)
      steps.assign(std::begin(EdgeFilter::kAutoLadder), std::end(EdgeFilter::kAutoLadder));
    else
      steps.push_back(-1);  // the filter's own count or fraction
    thread_local Accumulators acc;
    s.acc.resize(f.m);
    CutFinder cuts(s.max_density, s.histogram, s.bucket);
    for (std::size_t step = 0; step < steps.size() && out.admissible > 0; ++step) {
      // Keep the L - K smallest; ties at the cut are all kept.
      std::size_t drop = steps[step] < 0
                             ? filter.drop_count(out.admissible)
                             : EdgeFilter::fraction(steps[step]).drop_count(out.admissible);
      std::size_t keep = out.admissible - drop;
      float cut = cuts.kth(keep - 1);
      // Pass 2: sum the kept triples.
      std::size_t kept = sum_below(f, s.max_density.data(), cut, acc, s.acc.data());
      out.dropped = out.admissible - kept;
      std::fill(out.values.begin(), out.values.end(), 0.0);
      for (std::size_t p = 0; p < f.m; ++p)
        out.values[active_[s.order[p]]] = target.sum() * s.acc[p] / static_cast<double>(kept);
      if (bands_.free_of_peaks(out.values)) break;
    }
    return out;
  }
  std::size_t used = out.admissible - out.dropped;
  if (used > 0)
    for (double& v : out.values) v /= static_cast<double>(used);
  return out;
}

}  // namespace spectralize
