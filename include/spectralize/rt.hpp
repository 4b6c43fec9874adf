// spectralize::rt -- the C++ API (header-only, C++17, no dependencies) of the render-time
// evaluator of exact spectra; see <spectralize/rt.h> for the C API over it and
// docs/DESIGN.md §14 for the table and why it is exact.
//
//   spz::Table table;
//   std::string error;
//   if (!table.load("srgb.spztab", &error)) ...;        // never throws; checks what it means
//   spz::Spectrum s;
//   const int status = table.view().fetch(rgb, s);       // SPZ_EXACT, SPZ_MAPPED, < 0 invalid
//   float v[4];
//   spz::eval4(s, lambdas, v);                           // or spz::eval(s, 550.f)
//
// A TableView is a validated view of a table's bytes (owned by a Table, or any memory the
// caller keeps alive: a file mapped into memory, aligned to 8 bytes). Lookups read only and
// are thread-safe. fetch() and the eval functions allocate nothing, throw nothing and make no
// virtual calls; their data are plain arrays. Whatever the bytes and the colour: loading costs
// O(file size); a fetch at most O(the header's max_cell_simplices) inside the gamut and O(its
// planes) to map a colour in; no input is undefined behaviour; a fetch that says SPZ_EXACT or
// SPZ_MAPPED gives a finite spectrum >= 0 (<= 1 for reflectances), SPZ_EXACT only when it
// reproduces the colour to SPZ_EXACT_TOLERANCE at any magnitude.
#ifndef SPECTRALIZE_RT_HPP
#define SPECTRALIZE_RT_HPP

#include <spectralize/rt.h>
#include <spectralize/rt_format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/stat.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// The rare paths (boundary cells, colours mapped into the gamut) out of line and out of the
// hot code; eval4 into the caller's loop.
#if defined(__GNUC__)
#define SPZ_COLD __attribute__((noinline, cold))
#define SPZ_HOT_INLINE __attribute__((always_inline)) inline
#else
#define SPZ_COLD
#define SPZ_HOT_INLINE inline
#endif

namespace spz {

using Spectrum = spz_spectrum;

namespace detail {

// FNV-1a, 64 bit, as published (offset basis 14695981039346656037 = 0xcbf29ce484222325, prime
// 1099511628211): the hash of n bytes continuing from h (by default a hash from the start).
inline constexpr std::uint64_t kFnv1aOffsetBasis = 14695981039346656037ull;
inline std::uint64_t fnv1a(const unsigned char* p, std::size_t n,
                           std::uint64_t h = kFnv1aOffsetBasis) noexcept {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// The checksum of a table: FNV-1a 64 of the bytes with the checksum field (24..31) as zeros.
// The writer (src/core/table_file.cpp) computes it with this function too.
inline std::uint64_t table_checksum(const unsigned char* data, std::size_t size) noexcept {
  const unsigned char zeros[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::uint64_t h = kFnv1aOffsetBasis;
  h = fnv1a(data, 24, h);
  h = fnv1a(zeros, 8, h);
  return fnv1a(data + 32, size - 32, h);
}

inline void say(char* error, std::size_t size, const char* format, ...) noexcept {
  if (!error || size == 0) return;
  va_list args;
  va_start(args, format);
  std::vsnprintf(error, size, format, args);
  va_end(args);
}

// The bin of position v in an axis' lookup (spz_axis_bin): clamped before the cast, so that NaN
// (bin 0) and infinities are no undefined behaviour. The writer and the loader's check use
// this same float arithmetic.
inline std::uint32_t axis_bin(float v, float origin, float inverse_bin, float last_bin) noexcept {
  float b = (v - origin) * inverse_bin;
  b = b > 0.0f ? b : 0.0f;
  b = b < last_bin ? b : last_bin;
  return static_cast<std::uint32_t>(b);
}

inline bool finite(double v) noexcept {
  return std::isfinite(v);
}

struct Vec3 {
  double x, y, z;
};
inline double dot(const double* n, const Vec3& v) noexcept {
  return n[0] * v.x + n[1] * v.y + n[2] * v.z;
}
inline Vec3 mul(const double* m, const Vec3& v) noexcept {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}
inline double max_abs(const Vec3& v) noexcept {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

// The point of a simplex (4 vertices in 3-D; a triangle when `dims` is 2, p[3] ignored) closest
// to x, as barycentric weights w (>= 0, sum 1); returns the squared distance. Every face of
// the simplex is tried (the least-squares point of its affine hull, kept when its weights are
// >= 0): 15 small systems. For a colour within rounding of a clipped cell's boundary, the blend
// of its nearest point: off by that distance only. Cost: ~300 flops.
inline double closest_in_simplex(const double p[4][3], int dims, const double x[3],
                                 double w[4]) noexcept {
  const int nv = dims + 1;
  double best = 1e300;
  for (int mask = 1; mask < (1 << nv); ++mask) {
    int idx[4] = {0, 0, 0, 0}, m = 0;
    for (int v = 0; v < nv; ++v)
      if (mask & (1 << v)) idx[m++] = v;
    // x ~ p[idx0] + sum_k c_k (p[idx_k] - p[idx0]): normal equations G c = r (m - 1 unknowns).
    double e[3][3], G[3][3] = {}, r[3] = {}, c[3] = {0, 0, 0};
    for (int k = 1; k < m; ++k)
      for (int a = 0; a < 3; ++a) e[k - 1][a] = p[idx[k]][a] - p[idx[0]][a];
    const double d0[3] = {x[0] - p[idx[0]][0], x[1] - p[idx[0]][1], x[2] - p[idx[0]][2]};
    const int n = m - 1;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j)
        G[i][j] = e[i][0] * e[j][0] + e[i][1] * e[j][1] + e[i][2] * e[j][2];
      r[i] = e[i][0] * d0[0] + e[i][1] * d0[1] + e[i][2] * d0[2];
    }
    bool ok = true;
    if (n == 1) {
      ok = G[0][0] > 0;
      if (ok) c[0] = r[0] / G[0][0];
    } else if (n == 2) {
      const double D = G[0][0] * G[1][1] - G[0][1] * G[1][0];
      ok = D > 0;
      if (ok)
        c[0] = (r[0] * G[1][1] - G[0][1] * r[1]) / D, c[1] = (G[0][0] * r[1] - G[1][0] * r[0]) / D;
    } else if (n == 3) {
      const double D = G[0][0] * (G[1][1] * G[2][2] - G[1][2] * G[2][1]) -
                       G[0][1] * (G[1][0] * G[2][2] - G[1][2] * G[2][0]) +
                       G[0][2] * (G[1][0] * G[2][1] - G[1][1] * G[2][0]);
      ok = D > 0;
      if (ok)
        for (int k = 0; k < 3; ++k) {
          double H[3][3];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) H[i][j] = j == k ? r[i] : G[i][j];
          c[k] = (H[0][0] * (H[1][1] * H[2][2] - H[1][2] * H[2][1]) -
                  H[0][1] * (H[1][0] * H[2][2] - H[1][2] * H[2][0]) +
                  H[0][2] * (H[1][0] * H[2][1] - H[1][1] * H[2][0])) /
                 D;
        }
    }
    if (!ok) continue;
    double w0 = 1;
    for (int k = 0; k < n; ++k) {
      if (c[k] < 0) ok = false;
      w0 -= c[k];
    }
    if (!ok || w0 < 0) continue;
    double q[3] = {p[idx[0]][0], p[idx[0]][1], p[idx[0]][2]};
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) q[a] += c[k] * e[k][a];
    const double dist = (q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]) +
                        (q[2] - x[2]) * (q[2] - x[2]);
    if (dist < best) {
      best = dist;
      for (int v = 0; v < 4; ++v) w[v] = 0;
      w[idx[0]] = w0;
      for (int k = 0; k < n; ++k) w[idx[k + 1]] = c[k];
    }
  }
  return best;
}

// A half-space gamut in target XYZ, as the spectralize CLI tests it (docs/DESIGN.md §5).
struct Gamut {
  const double* planes = nullptr;  // n.x, n.y, n.z, d per plane
  std::uint64_t count = 0;
  bool contains(const Vec3& t) const noexcept {
    const double tol = 1e-12 * max_abs(t);  // relative: near black the gamuts are cones
    for (std::uint64_t f = 0; f < count; ++f)
      if (dot(planes + 4 * f, t) > planes[4 * f + 3] + tol) return false;
    return true;
  }
  double max_step(const Vec3& from, const Vec3& to) const noexcept {
    double s = 1.0;
    const Vec3 d{to.x - from.x, to.y - from.y, to.z - from.z};
    for (std::uint64_t f = 0; f < count; ++f) {
      const double* p = planes + 4 * f;
      if (dot(p, to) <= p[3]) continue;
      const double slack = p[3] - dot(p, from), rate = dot(p, d);
      if (rate > 0) s = std::min(s, std::max(slack, 0.0) / rate);
    }
    return s;
  }
};

}  // namespace detail

/// A validated, read-only view of a table's bytes.
class TableView {
 public:
  /// Validates `size` bytes at `data` (8-byte aligned; kept alive by the caller) as a table:
  /// header, sizes, offsets, counts, indices, values and checksum. False, with a message in
  /// `error`, for anything unusable; never reads outside [data, data + size). Cost: O(size).
  bool open(const void* data, std::size_t size, char* error, std::size_t error_size) noexcept;

  /// The spectrum of a linear RGB colour of the table's colour space: SPZ_EXACT (it reproduces
  /// the colour to SPZ_EXACT_TOLERANCE), SPZ_MAPPED (outside the gamut, or within rounding of
  /// its boundary: the spectrum of the colour mapped in, as the CLI maps it), SPZ_INVALID (NaN,
  /// infinite, a light too bright for its spectrum to be finite in float, or a view without a
  /// table) or SPZ_NEGATIVE (the zero spectrum). Cost: O(1) inside cells; O(max_cell_simplices)
  /// in a boundary cell; O(planes) for a mapped colour.
  int fetch(const float rgb[3], Spectrum& out) const noexcept;

  /// fetch() then eval4() at once, as a texture lookup that evaluates straight away does: the
  /// same status and values bit for bit, the spectrum kept out of memory on the common path
  /// (a colour inside a cell of a reflectance table); `keep`, if not null, gets it too. Cost:
  /// as fetch() and eval4(), a few cycles less.
  int fetch_eval4(const float rgb[3], const float lambda_nm[4], float out[4],
                  Spectrum* keep = nullptr) const noexcept;

  /// The gamut mapping alone (docs/DESIGN.md §5) of an RGB colour: the RGB the spectrum of
  /// `rgb` reproduces. Returns the fetch status of the colour. Cost: O(facets).
  int map_into_gamut(const double rgb[3], double mapped[3]) const noexcept;

  /// True for a view of a validated table (false: empty, moved from, or a failed open).
  bool loaded() const noexcept { return h_ != nullptr; }
  /// The empty view: its fetches give SPZ_INVALID and the zero spectrum. Cost: O(1).
  static const TableView& none() noexcept;
  std::size_t bands() const noexcept { return bands_; }
  /// Colours whose target X, Y, Z are all below this (table units: a reflectance's white has
  /// Y = 1) are black, SPZ_MAPPED: their float spectra would be denormal, not exact.
  static constexpr double kDarkest = 1e-30;
  float lambda_start() const noexcept { return start_; }
  float lambda_step() const noexcept { return step_; }
  bool reflectance() const noexcept { return reflectance_; }
  /// True when a reflectance colour in [0, 1]^3 finds its cell from its square root alone
  /// (the axes hold (k / steps)^2 on [0, 1], as `spectralize table` writes them), without the
  /// lookup bins. Cost: O(1).
  bool direct_lookup() const noexcept { return direct_; }
  const spz_file_header& header() const noexcept { return *h_; }

  // Internal data, read by the eval functions below.
  std::uint32_t bands_ = 0, mask_words_ = 0;
  float start_ = 0, step_ = 1, inv_step_ = 1, last_ = 0;
  bool reflectance_ = false;
  const spz_file_header* h_ = nullptr;
  const float* spectra_ = nullptr;
  const std::uint32_t* bmask_ = nullptr;
  const std::uint32_t* bpick_ = nullptr;
  const float* bvalue_ = nullptr;
  // eval4's constants in its four lanes: start, 1 / step, last band, last interval, step.
  alignas(16) float wave_[5][4] = {};

 private:
  bool locate(const double u[3], int cell_index[3], double f[3], bool clamp,
              bool* moved = nullptr) const noexcept;
  bool blend(const double u[3], Spectrum& s, bool nearest, bool* reproduced) const noexcept;
  template <int dims>
  bool fast_blend(const float u[3], Spectrum& s) const noexcept;
  // fetch()'s common path for a reflectance: the spectrum's fields, and the lookup of a colour
  // not darker than kDarkest inside a cell (kBoundary: in a boundary cell too). False: the
  // colour goes the slow way.
  template <bool kBoundary>
  bool fast_reflectance(const float rgb[3], Spectrum& s) const noexcept;
  struct AxisFast {  // one axis' lookup, hot in fetch()
    const spz_axis_bin* lut;
    float origin, inv_bin, last_bin, lo, hi;
    std::uint32_t last;  // last_bin as an integer
  };
  AxisFast fast_[3] = {};
#if defined(__SSE2__)
  // fetch()'s reflectance lookup in SSE lanes (x, y, z, unused): the three axes at once.
  // kBoundary false: a boundary cell returns false (the caller fetches it the full way), so
  // that the spectrum's address never escapes and it can stay in registers.
  template <bool kBoundary = true>
  bool fast_blend_sse(const float rgb[3], Spectrum& s) const noexcept;
  struct Lanes {
    alignas(16) float lo[4] = {}, hi[4] = {}, origin[4] = {}, inv_bin[4] = {};
    alignas(16) std::int32_t last[4] = {};    // each axis' last bin
    alignas(16) std::int32_t lut_at[4] = {};  // each axis' first bin, counted from lut_[0]
    // By the order code of the fractions (bit 0: f1 > f0, bit 1: f2 > f0, bit 2: f2 > f1): the
    // slot offsets of the Kuhn walk's first vertex and of its second, and the axes from the
    // largest fraction to the smallest.
    std::uint32_t first[8] = {}, second[8] = {};
    std::uint32_t far = 0;  // the node offset of the cell's highest corner: 1 + nx + nx * ny
    std::uint8_t order[8][3] = {};
    // The squared nodes of [0, 1] ((k / steps)^2, k = 0..steps on every axis, as the writer
    // places them): there the interval is k = floor(steps * sqrt(v)), no lookup read at all.
    std::uint32_t zero_node = 0;  // the node offset of (0, 0, 0)
    alignas(16) float steps[4] = {}, last_k[4] = {}, steps2[4] = {};  // steps, steps - 1, steps^2
    alignas(16) float stride[4] = {};  // each axis' node stride (lane 3: 0)
  };
  Lanes lanes_;
  // True when every axis holds (k / steps)^2 for k = 0..steps (float of the double square, as
  // the writer stores them) consecutively, the same steps on each: sets the node offset of
  // black and steps. Cost: O(steps).
  bool squared_axes(std::uint32_t& zero_node, float& steps) const noexcept;
#endif
  bool cell_blend(const int i[3], const double f[3], const double u[3], Spectrum& s, bool nearest,
                  bool* reproduced) const noexcept;
  // A fast lookup's boundary cell, named by its code and its lowest node (cold).
  bool boundary_of_node(std::uint32_t code, std::uint32_t node, const double u[3],
                        Spectrum& s) const noexcept;
  bool boundary_blend(std::uint32_t b, const int i[3], const double u[3], Spectrum& s, bool nearest,
                      bool* reproduced) const noexcept;
  bool close_to(const double u[3], const double v[3]) const noexcept;
  std::uint32_t slot_of_corner(const int i[3], std::uint32_t corner) const noexcept {
    const std::uint32_t x = static_cast<std::uint32_t>(i[0]) + (corner & 1u);
    const std::uint32_t y = static_cast<std::uint32_t>(i[1]) + ((corner >> 1) & 1u);
    const std::uint32_t z = static_cast<std::uint32_t>(i[2]) + ((corner >> 2) & 1u);
    return slots_[x + n_[0] * (y + n_[1] * z)];
  }
  static void zero(Spectrum& s) noexcept {
    for (int k = 0; k < 4; ++k) s.vertex[k] = 0, s.weight[k] = 0;
    s.scale = 0;
    s.flags &= ~1u;
  }
  int slow_fetch(const float rgb[3], Spectrum& s) const noexcept;
  int map_target(detail::Vec3& t) const noexcept;
  bool check_meaning(char* error, std::size_t error_size) const noexcept;

  std::uint32_t n_[3] = {0, 0, 0}, lut_size_[3] = {0, 0, 0}, dims_ = 3;
  std::uint32_t stride_[3] = {0, 0, 0};  // each axis' node stride: 1, nx, nx * ny
  bool direct_ = false;                  // direct_lookup()
  float lut_origin_[3] = {0, 0, 0}, lut_inv_[3] = {0, 0, 0};
  const float* axis_[3] = {nullptr, nullptr, nullptr};
  const float* inverse_[3] = {nullptr, nullptr, nullptr};
  const spz_axis_bin* lut_[3] = {nullptr, nullptr, nullptr};
  const std::uint32_t* cells_ = nullptr;
  const std::uint32_t* slots_ = nullptr;
  const std::uint32_t* bcells_ = nullptr;
  const std::uint32_t* simplices_ = nullptr;
  const double* bpos_ = nullptr;
  float to_target_f_[9] = {};
  float max_scale_ = 0;  // emission: the largest X+Y+Z whose spectrum stays finite in float
  const double* band_weights_ = nullptr;
  detail::Gamut locus_, solid_;
};

/// A table read from a file (owns its bytes). Movable, not copyable. Its view lives beside the
/// bytes on the heap, so spectra fetched from it stay valid when the Table object moves; a
/// Table never loaded, moved from, or whose last load failed has an empty view, whose fetches
/// give SPZ_INVALID and the zero spectrum.
class Table {
 public:
  Table() = default;
  Table(Table&& o) noexcept { *this = static_cast<Table&&>(o); }
  Table& operator=(Table&& o) noexcept {
    if (this != &o) {
      release();
      block_ = o.block_, view_ = o.view_;
      o.block_ = nullptr, o.view_ = nullptr;
    }
    return *this;
  }
  Table(const Table&) = delete;
  Table& operator=(const Table&) = delete;
  ~Table() { release(); }

  /// Reads and validates a table file: its 1024-byte header first (signature, version, size),
  /// then the rest. False with "PATH: reason" in error (when not null), and an empty view (the
  /// table held before is released either way). Never throws. Cost: O(file size).
  bool load(const char* path, char* error, std::size_t error_size) noexcept;
  bool load(const char* path, std::string* error = nullptr) {
    char buf[512];
    const bool ok = load(path, buf, sizeof buf);
    if (!ok && error) *error = buf;
    return ok;
  }
  /// The validated view, or an empty one. Cost: O(1).
  const TableView& view() const noexcept { return view_ ? *view_ : TableView::none(); }

 private:
  void release() noexcept {
    if (view_) view_->~TableView();
    std::free(block_);
    block_ = nullptr, view_ = nullptr;
  }
  unsigned char* block_ = nullptr;  // the view, then the file's bytes at kBytesAt
  TableView* view_ = nullptr;
  static constexpr std::size_t kBytesAt = (sizeof(TableView) + 63) / 64 * 64;
};

namespace detail {

// Sample k of spectrum vertex v of s (a node spectrum, or a boundary vertex's 0/1 mask with two
// samples of their own).
inline float vertex_value(const TableView& t, std::uint32_t v, std::uint32_t k) noexcept {
  if (!(v & SPZ_BOUNDARY_BIT)) return t.spectra_[static_cast<std::size_t>(v) + k];
  const std::uint32_t b = v & ~SPZ_BOUNDARY_BIT, pick = t.bpick_[b];
  if (k == (pick & 0xFFFFu)) return t.bvalue_[2 * static_cast<std::size_t>(b)];
  if (k == (pick >> 16)) return t.bvalue_[2 * static_cast<std::size_t>(b) + 1];
  return static_cast<float>(
      (t.bmask_[static_cast<std::size_t>(b) * t.mask_words_ + k / 32] >> (k % 32)) & 1u);
}

}  // namespace detail

/// The spectrum's value at `lambda_nm`: the piecewise-linear function through its samples, 0
/// outside the table's wavelengths. Cost: O(1), 8 loads.
namespace detail {

// The sample interval of a wavelength and the position in it. The fraction is taken from the
// interval's own start (exact in float for grids of whole nanometres), not from the position
// on the whole grid, whose float rounding would be ~1e-5 of a sample apart at 780 nm.
inline void interval_of(const TableView& t, float lambda_nm, std::uint32_t& k, float& f) noexcept {
  const float x = (lambda_nm - t.start_) * t.inv_step_;
  k = std::min(static_cast<std::uint32_t>(x), t.bands_ - 2);
  f = (lambda_nm - (t.start_ + static_cast<float>(k) * t.step_)) * t.inv_step_;
  f = std::min(std::max(f, 0.0f), 1.0f);
}

}  // namespace detail

namespace detail {

// The one arithmetic of eval, eval4's lanes and max_value, in the order of eval4's SSE lanes
// (bit for bit): the weighted sums of the vertices' samples at k (x) and k + 1 (y), each as two
// pairs, blended at fraction f; a reflectance clamped to 1 (rounding only), a light times its
// scale.
inline float blend_value(const Spectrum& s, const float x[4], const float y[4], float f) noexcept {
  const float a =
      (s.weight[0] * x[0] + s.weight[1] * x[1]) + (s.weight[2] * x[2] + s.weight[3] * x[3]);
  const float b =
      (s.weight[0] * y[0] + s.weight[1] * y[1]) + (s.weight[2] * y[2] + s.weight[3] * y[3]);
  const float v = (1 - f) * a + f * b;
  return (s.flags & 2u) ? std::min(v, 1.0f) : v * s.scale;
}

}  // namespace detail

inline float eval(const Spectrum& s, float lambda_nm) noexcept {
  if (!s.table) return 0.0f;  // the zero spectrum (e.g. zero-initialised)
  const TableView& t = *static_cast<const TableView*>(s.table);
  const float x = (lambda_nm - t.start_) * t.inv_step_;
  if (!(x >= 0.0f && x <= t.last_)) return 0.0f;
  std::uint32_t k;
  float f;
  detail::interval_of(t, lambda_nm, k, f);
  float at[4], next[4];  // the vertices' samples at k and k + 1
  for (int v = 0; v < 4; ++v) {
    at[v] = detail::vertex_value(t, s.vertex[v], k);
    next[v] = detail::vertex_value(t, s.vertex[v], k + 1);
  }
  return detail::blend_value(s, at, next, f);
}

/// The values at four wavelengths. Cost: O(1), 32 loads; the arithmetic in SSE lanes where
/// the compiler targets SSE2 (every x86-64), else the same in plain C++.
SPZ_HOT_INLINE void eval4(const Spectrum& s, const float lambda_nm[4], float out[4]) noexcept {
  if (!s.table) {  // the zero spectrum (e.g. zero-initialised)
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    return;
  }
  const TableView& t = *static_cast<const TableView*>(s.table);
#if defined(__SSE2__)
  if (!(s.flags & 1u)) {
    const __m128 l = _mm_loadu_ps(lambda_nm), start = _mm_load_ps(t.wave_[0]);
    const __m128 inv = _mm_load_ps(t.wave_[1]), zero = _mm_setzero_ps(), one = _mm_set1_ps(1);
    const __m128 x = _mm_mul_ps(_mm_sub_ps(l, start), inv);
    const __m128 in = _mm_and_ps(_mm_cmpge_ps(x, zero), _mm_cmple_ps(x, _mm_load_ps(t.wave_[2])));
    // The interval (k <= N - 2) and the position in it from its own start (interval_of).
    const __m128 xk = _mm_min_ps(_mm_and_ps(in, x), _mm_load_ps(t.wave_[3]));
    const __m128i ki = _mm_cvttps_epi32(xk);
    const __m128 lk = _mm_add_ps(start, _mm_mul_ps(_mm_cvtepi32_ps(ki), _mm_load_ps(t.wave_[4])));
    const __m128 lc = _mm_or_ps(_mm_and_ps(in, l), _mm_andnot_ps(in, start));
    const __m128 f = _mm_max_ps(_mm_min_ps(_mm_mul_ps(_mm_sub_ps(lc, lk), inv), one), zero);
    const int k0 = _mm_cvtsi128_si32(ki), k1 = _mm_cvtsi128_si32(_mm_shuffle_epi32(ki, 0x55));
    const int k2 = _mm_cvtsi128_si32(_mm_shuffle_epi32(ki, 0xAA));
    const int k3 = _mm_cvtsi128_si32(_mm_shuffle_epi32(ki, 0xFF));
    // The weighted sums of the samples at k and k + 1 (each lane's two samples in one 8-byte
    // load; the four vertices summed as two pairs), then one blend per lane: a short chain
    // from the vertices to the values.
    __m128 lo[4], hi[4];
    for (int v = 0; v < 4; ++v) {
      const float* p = t.spectra_ + s.vertex[v];  // the spectrum's offset (rt_format.h)
      const __m128 w = _mm_set1_ps(s.weight[v]);
      lo[v] = _mm_mul_ps(w, _mm_loadh_pi(_mm_loadl_pi(zero, reinterpret_cast<const __m64*>(p + k0)),
                                         reinterpret_cast<const __m64*>(p + k1)));
      hi[v] = _mm_mul_ps(w, _mm_loadh_pi(_mm_loadl_pi(zero, reinterpret_cast<const __m64*>(p + k2)),
                                         reinterpret_cast<const __m64*>(p + k3)));
    }
    const __m128 acc01 = _mm_add_ps(_mm_add_ps(lo[0], lo[1]), _mm_add_ps(lo[2], lo[3]));
    const __m128 acc23 = _mm_add_ps(_mm_add_ps(hi[0], hi[1]), _mm_add_ps(hi[2], hi[3]));
    const __m128 a = _mm_shuffle_ps(acc01, acc23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 b = _mm_shuffle_ps(acc01, acc23, _MM_SHUFFLE(3, 1, 3, 1));
    __m128 acc = _mm_add_ps(_mm_mul_ps(_mm_sub_ps(one, f), a), _mm_mul_ps(f, b));
    acc = (s.flags & 2u) ? _mm_min_ps(acc, one) : _mm_mul_ps(acc, _mm_set1_ps(s.scale));
    acc = _mm_and_ps(in, acc);
    _mm_storeu_ps(out, acc);
    return;
  }
#endif
  std::uint32_t k[4];
  float f[4];
  bool in[4];
  for (int l = 0; l < 4; ++l) {
    const float x = (lambda_nm[l] - t.start_) * t.inv_step_;
    in[l] = x >= 0.0f && x <= t.last_;
    detail::interval_of(t, in[l] ? lambda_nm[l] : t.start_, k[l], f[l]);
  }
  for (int l = 0; l < 4; ++l) {
    float x[4], y[4];
    for (int v = 0; v < 4; ++v) {
      x[v] = detail::vertex_value(t, s.vertex[v], k[l]);
      y[v] = detail::vertex_value(t, s.vertex[v], k[l] + 1);
    }
    out[l] = in[l] ? detail::blend_value(s, x, y, f[l]) : 0.0f;
  }
}

/// Every sample of the spectrum (bands() floats). Cost: O(bands).
inline void samples(const Spectrum& s, float* out) noexcept {
  if (!s.table) return;  // the zero spectrum has no bands: see samples(s, out, capacity)
  const TableView& t = *static_cast<const TableView*>(s.table);
  const std::uint32_t n = t.bands_;
  const bool clamp = (s.flags & 2u) != 0;
  if (!(s.flags & 1u)) {
    const float* p0 = t.spectra_ + s.vertex[0];
    const float* p1 = t.spectra_ + s.vertex[1];
    const float* p2 = t.spectra_ + s.vertex[2];
    const float* p3 = t.spectra_ + s.vertex[3];
    const float w0 = s.weight[0] * s.scale, w1 = s.weight[1] * s.scale;
    const float w2 = s.weight[2] * s.scale, w3 = s.weight[3] * s.scale;
    if (clamp)
      for (std::uint32_t k = 0; k < n; ++k)
        out[k] = std::min(w0 * p0[k] + w1 * p1[k] + w2 * p2[k] + w3 * p3[k], 1.0f);
    else
      for (std::uint32_t k = 0; k < n; ++k)
        out[k] = w0 * p0[k] + w1 * p1[k] + w2 * p2[k] + w3 * p3[k];
    return;
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    float acc = 0;
    for (int v = 0; v < 4; ++v) acc += s.weight[v] * detail::vertex_value(t, s.vertex[v], k);
    acc *= s.scale;
    out[k] = clamp ? std::min(acc, 1.0f) : acc;
  }
}

/// The samples of the spectrum into `out`, at most `capacity` of them: returns its band count
/// (its samples are written when it is <= capacity; else nothing is). The zero spectrum of no
/// table writes `capacity` zeros and returns 0. Cost: O(bands).
inline std::size_t samples(const Spectrum& s, float* out, std::size_t capacity) noexcept {
  if (!s.table) {
    for (std::size_t k = 0; k < capacity; ++k) out[k] = 0.0f;
    return 0;
  }
  const std::size_t n = static_cast<const TableView*>(s.table)->bands();
  if (n <= capacity) samples(s, out);
  return n;
}

/// An upper bound of the spectrum's values at every wavelength, eval's and eval4's: its largest
/// sample with 8 ulp of room for their rounding (0 for the zero spectrum; pbrt's MaxValue(), a
/// medium's majorant). Cost: O(bands).
inline float max_value(const Spectrum& s) noexcept {
  if (!s.table) return 0.0f;
  const TableView& t = *static_cast<const TableView*>(s.table);
  float most = 0;
  for (std::uint32_t k = 0; k < t.bands_; ++k) {
    float x[4];
    for (int v = 0; v < 4; ++v) x[v] = detail::vertex_value(t, s.vertex[v], k);
    most = std::max(most, detail::blend_value(s, x, x, 0.0f));
  }
  // Between samples eval blends the two, which rounds a few ulp above the larger: 8 ulp of
  // room, so that no value eval returns exceeds the bound.
  return (s.flags & 2u) ? std::min(most * (1.0f + 0x1p-21f), 1.0f) : most * (1.0f + 0x1p-21f);
}

/// The number of samples of the spectrum (0 for the zero spectrum of no table). Cost: O(1).
inline std::size_t bands(const Spectrum& s) noexcept {
  return s.table ? static_cast<const TableView*>(s.table)->bands() : 0;
}

/// The spectra of n colours (rgb: 3n floats) into out, row by row: at the m wavelengths of
/// lambda_nm, or (lambda_nm null) at the table's own bands. Statuses per colour (if not null)
/// and their counts (if not null: exact, mapped, invalid, negative). Returns the row length (m
/// or bands()). Thread-safe: threads may fill disjoint rows. Cost: n fetches and n * row
/// evaluations.
inline std::size_t fetch_array(const TableView& t, const float* rgb, std::size_t n,
                               const float* lambda_nm, std::size_t m, float* out, int* statuses,
                               std::size_t counts[4]) noexcept;

// --- TableView ---

namespace detail {

// The names of the sections, for messages.
inline const char* section_name(int s) noexcept {
  static const char* const names[SPZ_SECTION_COUNT] = {"axis x",
                                                       "axis y",
                                                       "axis z",
                                                       "axis inverse",
                                                       "axis lookup",
                                                       "cells",
                                                       "node slots",
                                                       "spectra",
                                                       "boundary cells",
                                                       "simplices",
                                                       "boundary positions",
                                                       "boundary masks",
                                                       "boundary picks",
                                                       "boundary values",
                                                       "locus planes",
                                                       "solid planes",
                                                       "band weights"};
  return s >= 0 && s < static_cast<int>(SPZ_SECTION_COUNT) ? names[s] : "?";
}

// The header of a table: its signature, byte order, version and size against `size` bytes of
// file (all a reader checks before reading the rest).
inline bool check_header_start(const spz_file_header* h, std::size_t size, char* error,
                               std::size_t error_size) noexcept {
  if (std::memcmp(h->magic, "SPZTABLE", 8) != 0)
    return say(error, error_size, "not a spectralize table (no SPZTABLE signature)"), false;
  const std::uint32_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  if (first != 1)
    return say(error, error_size, "this evaluator runs on little-endian machines only"), false;
  if (h->byte_order != SPZ_BYTE_ORDER_MARK) {
    say(error, error_size,
        h->byte_order == 0x04030201u ? "written with the wrong byte order (big-endian)"
                                     : "bad byte_order mark 0x%08x",
        static_cast<unsigned>(h->byte_order));
    return false;
  }
  if (h->version != SPZ_FORMAT_VERSION) {
    say(error, error_size,
        h->version < SPZ_FORMAT_VERSION
            ? "format version %u: this evaluator reads version %u; make the table again with "
              "`spectralize table`"
            : "format version %u: this evaluator reads version %u; use a newer evaluator",
        static_cast<unsigned>(h->version), SPZ_FORMAT_VERSION);
    return false;
  }
  if (h->header_size != SPZ_HEADER_SIZE)
    return say(error, error_size, "bad header_size %u (not %u)", h->header_size, SPZ_HEADER_SIZE),
           false;
  if (h->file_size != size) {
    say(error, error_size, "%s: file_size says %llu bytes, there are %zu",
        h->file_size > size ? "truncated" : "extra bytes",
        static_cast<unsigned long long>(h->file_size), size);
    return false;
  }
  return true;
}

// The largest difference between the product of two 3 x 3 row-major matrices and the identity.
inline double inverse_error(const double* a, const double* b) noexcept {
  double worst = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const double v = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
      worst = std::max(worst, std::abs(v - (r == c ? 1.0 : 0.0)));
    }
  return worst;
}

inline double det3(const double* m) noexcept {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

}  // namespace detail

inline bool TableView::open(const void* data, std::size_t size, char* error,
                            std::size_t error_size) noexcept {
  using detail::say;
  const auto* bytes = static_cast<const unsigned char*>(data);
  *this = TableView{};
  if (!data || size < SPZ_HEADER_SIZE) {
    say(error, error_size, "truncated: %zu bytes, a table has a %u-byte header at least", size,
        SPZ_HEADER_SIZE);
    return false;
  }
  if (reinterpret_cast<std::uintptr_t>(data) % 8 != 0) {
    say(error, error_size, "the table's bytes are not 8-byte aligned in memory");
    return false;
  }
  const auto* h = static_cast<const spz_file_header*>(data);
  if (!detail::check_header_start(h, size, error, error_size)) return false;
  if (h->section_count != SPZ_SECTION_COUNT)
    return say(error, error_size, "bad section_count %u (not %u)", h->section_count,
               SPZ_SECTION_COUNT),
           false;
  if (detail::table_checksum(bytes, size) != h->checksum) {
    say(error, error_size, "checksum mismatch (the file is corrupt)");
    return false;
  }
  // Fixed fields.
  const bool reflectance = h->mode == SPZ_MODE_REFLECTANCE;
  if (h->mode != SPZ_MODE_EMISSION && !reflectance)
    return say(error, error_size, "bad mode %u", h->mode), false;
  if (h->bands < 2 || h->bands > SPZ_MAX_BANDS || h->mask_words != (h->bands + 31) / 32)
    return say(error, error_size, "bad bands %u or mask_words %u", h->bands, h->mask_words), false;
  // Wavelengths a float can step through (eval divides by the step in float).
  if (!(h->lambda_start >= 0 && h->lambda_start < 1e5))
    return say(error, error_size, "bad lambda_start %g nm", h->lambda_start), false;
  if (!(h->lambda_step >= 1e-3 && h->lambda_step <= 1e4) ||
      !(h->lambda_start + h->lambda_step * (h->bands - 1) < 1e5))
    return say(error, error_size, "bad lambda_step %g nm (1e-3 to 1e4, the last band below 1e5 nm)",
               h->lambda_step),
           false;
  const double* matrices[] = {h->rgb_to_xyz, h->rgb_to_target, h->target_to_rgb};
  const char* matrix_names[] = {"rgb_to_xyz", "rgb_to_target", "target_to_rgb"};
  for (int m = 0; m < 3; ++m) {
    for (int k = 0; k < 9; ++k)
      if (!detail::finite(matrices[m][k]))
        return say(error, error_size, "%s is not finite", matrix_names[m]), false;
    if (!(std::abs(detail::det3(matrices[m])) > 1e-9))
      return say(error, error_size, "%s is singular", matrix_names[m]), false;
  }
  if (!(detail::inverse_error(h->rgb_to_target, h->target_to_rgb) <= 1e-6))
    return say(error, error_size, "target_to_rgb is not the inverse of rgb_to_target"), false;
  for (int k = 0; k < 3; ++k)
    if (!detail::finite(h->locus_white[k]) || !detail::finite(h->solid_white[k]))
      return say(error, error_size, "locus_white or solid_white is not finite"), false;
  if (!(h->locus_white[1] > 0)) return say(error, error_size, "bad locus_white"), false;
  if (reflectance && !(std::abs(h->solid_white[1] - 1) <= 1e-6))
    return say(error, error_size, "bad solid_white (its Y is not 1)"), false;
  // The mapping's parameters, within what the writer uses (a snap tolerance of 0.5 would call
  // any colour exact).
  if (!(h->locus_margin >= 0 && h->locus_margin <= 0.01) ||
      !(h->solid_margin >= 0 && h->solid_margin <= 0.01))
    return say(error, error_size, "bad locus_margin or solid_margin (0 to 0.01)"), false;
  if (!(h->snap_tolerance >= 0 && h->snap_tolerance <= 1e-5))
    return say(error, error_size, "bad snap_tolerance %g (0 to 1e-5)", h->snap_tolerance), false;
  if (!(h->locus_scale >= 0 && h->locus_scale < 1e30) ||
      !(h->solid_scale >= 0 && h->solid_scale < 1e30))
    return say(error, error_size, "bad locus_scale or solid_scale"), false;
  if (!(h->sample_bound > 0 && h->sample_bound < 1e30) || (reflectance && h->sample_bound > 1))
    return say(error, error_size, "bad sample_bound %g", h->sample_bound), false;
  if (h->max_cell_simplices > SPZ_MAX_CELL_SIMPLICES || h->reserved != 0)
    return say(error, error_size, "bad max_cell_simplices %u (at most %u) or reserved",
               h->max_cell_simplices, SPZ_MAX_CELL_SIMPLICES),
           false;
  const char* strings[] = {h->colorspace, h->interop_id,     h->model,    h->observer,
                           h->illuminant, h->emission_basis, h->generator};
  const char* string_names[] = {"colorspace", "interop_id",     "model",    "observer",
                                "illuminant", "emission_basis", "generator"};
  const std::size_t lengths[] = {
      sizeof h->colorspace, sizeof h->interop_id,     sizeof h->model,    sizeof h->observer,
      sizeof h->illuminant, sizeof h->emission_basis, sizeof h->generator};
  for (int k = 0; k < 7; ++k)
    if (!std::memchr(strings[k], 0, lengths[k]))
      return say(error, error_size, "%s is not terminated", string_names[k]), false;
  dims_ = reflectance ? 3 : 2;
  std::uint64_t nodes = 1;
  for (int a = 0; a < 3; ++a) {
    const std::uint32_t n = h->nodes[a];
    if (a < static_cast<int>(dims_) ? (n < 2 || n > 65536) : n != 1)
      return say(error, error_size, "bad nodes[%d] %u", a, n), false;
    nodes *= n;
    if (!(h->lut_size[a] >= 1 && h->lut_size[a] <= (1u << 20)) ||
        !std::isfinite(h->lut_origin[a]) || !(h->lut_inverse_bin[a] > 0) ||
        !std::isfinite(h->lut_inverse_bin[a]))
      return say(error, error_size, "bad lut_size, lut_origin or lut_inverse_bin of axis %d", a),
             false;
  }
  if (nodes > (1u << 28))
    return say(error, error_size, "too many nodes (%llu)", static_cast<unsigned long long>(nodes)),
           false;
  // Sections: aligned, inside the file, counts consistent with the header.
  const std::size_t element[SPZ_SECTION_COUNT] = {4, 4, 4, 4, 16, 4, 4, 4, 4,
                                                  4, 8, 4, 4, 4,  8, 8, 8};
  const void* at[SPZ_SECTION_COUNT];
  std::uint64_t count[SPZ_SECTION_COUNT];
  for (int s = 0; s < static_cast<int>(SPZ_SECTION_COUNT); ++s) {
    const spz_section_entry& e = h->sections[s];
    count[s] = e.count;
    if (e.count == 0) {
      at[s] = nullptr;
      continue;
    }
    if (e.offset % SPZ_SECTION_ALIGNMENT != 0 || e.offset < SPZ_HEADER_SIZE || e.offset > size ||
        e.count > (size - e.offset) / element[s])
      return say(error, error_size, "section '%s' lies outside the file or is misaligned",
                 detail::section_name(s)),
             false;
    at[s] = bytes + e.offset;
  }
  const std::uint32_t bands = h->bands;
  std::uint64_t intervals = 0, lut_total = 0;
  for (int a = 0; a < 3; ++a) {
    if (a < static_cast<int>(dims_)) intervals += h->nodes[a] - 1;
    lut_total += h->lut_size[a];
  }
  const std::uint64_t slots = count[SPZ_SECTION_SPECTRA] / bands;
  const std::uint64_t nbv = count[SPZ_SECTION_BOUNDARY_PICKS];
  const std::uint64_t nbc = count[SPZ_SECTION_BOUNDARY_CELLS] / 2;
  const std::uint64_t nsimplex = count[SPZ_SECTION_SIMPLICES] / 4;
  // Each count the header implies, by section: the first that disagrees is named.
  struct Expect {
    int section;
    bool ok;
    const char* what;
  };
  const std::uint64_t locus_planes = count[SPZ_SECTION_LOCUS_PLANES] / 4;
  const std::uint64_t solid_planes = count[SPZ_SECTION_SOLID_PLANES] / 4;
  const Expect expects[] = {
      {SPZ_SECTION_AXIS_X, count[SPZ_SECTION_AXIS_X] == h->nodes[0], "nodes[0] positions"},
      {SPZ_SECTION_AXIS_Y, count[SPZ_SECTION_AXIS_Y] == h->nodes[1], "nodes[1] positions"},
      {SPZ_SECTION_AXIS_Z, count[SPZ_SECTION_AXIS_Z] == h->nodes[2], "nodes[2] positions"},
      {SPZ_SECTION_AXIS_INVERSE, count[SPZ_SECTION_AXIS_INVERSE] == intervals, "one per interval"},
      {SPZ_SECTION_AXIS_LUT, count[SPZ_SECTION_AXIS_LUT] == lut_total + 1,
       "the lut_sizes' sum and one"},
      {SPZ_SECTION_CELLS, count[SPZ_SECTION_CELLS] == nodes, "one per node"},
      {SPZ_SECTION_NODE_SLOTS, count[SPZ_SECTION_NODE_SLOTS] == nodes, "one per node"},
      {SPZ_SECTION_SPECTRA,
       count[SPZ_SECTION_SPECTRA] % bands == 0 && slots >= 1 &&
           count[SPZ_SECTION_SPECTRA] < SPZ_BOUNDARY_BIT,
       "whole spectra of `bands` samples, at least one, fewer than 2^31 samples"},
      {SPZ_SECTION_BOUNDARY_CELLS,
       count[SPZ_SECTION_BOUNDARY_CELLS] % 2 == 0 && nbc < SPZ_BOUNDARY_BIT, "pairs"},
      {SPZ_SECTION_SIMPLICES, count[SPZ_SECTION_SIMPLICES] % 4 == 0, "four references each"},
      {SPZ_SECTION_BOUNDARY_PICKS, nbv < SPZ_BOUNDARY_BIT, "fewer than 2^31"},
      {SPZ_SECTION_BOUNDARY_POSITIONS, count[SPZ_SECTION_BOUNDARY_POSITIONS] == 3 * nbv,
       "three per boundary vertex"},
      {SPZ_SECTION_BOUNDARY_MASKS, count[SPZ_SECTION_BOUNDARY_MASKS] == nbv * h->mask_words,
       "mask_words per boundary vertex"},
      {SPZ_SECTION_BOUNDARY_VALUES, count[SPZ_SECTION_BOUNDARY_VALUES] == 2 * nbv,
       "two per boundary vertex"},
      {SPZ_SECTION_LOCUS_PLANES,
       count[SPZ_SECTION_LOCUS_PLANES] % 4 == 0 && locus_planes > 0 &&
           locus_planes <= SPZ_MAX_GAMUT_PLANES,
       "1 to SPZ_MAX_GAMUT_PLANES planes of four"},
      {SPZ_SECTION_SOLID_PLANES,
       count[SPZ_SECTION_SOLID_PLANES] % 4 == 0 && solid_planes <= SPZ_MAX_GAMUT_PLANES &&
           (reflectance ? solid_planes > 0 : solid_planes == 0),
       "planes of four (reflectance: 1 to SPZ_MAX_GAMUT_PLANES; emission: none)"},
      {SPZ_SECTION_BAND_WEIGHTS, count[SPZ_SECTION_BAND_WEIGHTS] == 3 * std::uint64_t{bands},
       "three per band"}};
  for (const Expect& e : expects)
    if (!e.ok)
      return say(error, error_size, "section '%s' holds %llu elements, not %s",
                 detail::section_name(e.section), static_cast<unsigned long long>(count[e.section]),
                 e.what),
             false;
  // Contents.
  auto u32 = [&](int s) { return static_cast<const std::uint32_t*>(at[s]); };
  auto f64 = [&](int s) { return static_cast<const double*>(at[s]); };
  std::uint64_t inv_at = 0, lut_at = 0;
  // Each axis' node stride (the nodes fit the file, so these fit 32 bits).
  const std::uint64_t stride[3] = {1, h->nodes[0], std::uint64_t{h->nodes[0]} * h->nodes[1]};
  for (int a = 0; a < 3; ++a) {
    n_[a] = h->nodes[a];
    stride_[a] = static_cast<std::uint32_t>(stride[a]);
    axis_[a] = static_cast<const float*>(at[SPZ_SECTION_AXIS_X + a]);
    for (std::uint32_t k = 0; k < n_[a]; ++k)
      if (!std::isfinite(axis_[a][k]) || (k > 0 && !(axis_[a][k] > axis_[a][k - 1])))
        return say(error, error_size, "axis %d is not increasing", a), false;
    if (a < static_cast<int>(dims_)) {
      inverse_[a] = static_cast<const float*>(at[SPZ_SECTION_AXIS_INVERSE]) + inv_at;
      for (std::uint32_t k = 0; k + 1 < n_[a]; ++k) {
        // 1 / the interval, as the writer rounds it to float (from the double interval).
        const double want = 1.0 / (static_cast<double>(axis_[a][k + 1]) - axis_[a][k]);
        if (!(std::abs(inverse_[a][k] - want) <= 1e-4 * want))
          return say(error, error_size, "axis inverse %u of axis %d is not 1 / its interval", k, a),
                 false;
      }
      inv_at += n_[a] - 1;
    }
    lut_[a] = static_cast<const spz_axis_bin*>(at[SPZ_SECTION_AXIS_LUT]) + lut_at;
    lut_size_[a] = h->lut_size[a];
    lut_origin_[a] = h->lut_origin[a];
    lut_inv_[a] = h->lut_inverse_bin[a];
    // Bins no wider than half the shortest interval; each names the interior nodes of lower
    // bins and the one inside it (spz_axis_bin), exactly as the writer makes it: the bins are
    // those of detail::axis_bin, the same float arithmetic as the lookup's.
    if (n_[a] > 1) {
      float shortest = INFINITY;
      for (std::uint32_t k = 0; k + 1 < n_[a]; ++k)
        shortest = std::min(shortest, axis_[a][k + 1] - axis_[a][k]);
      if (!(1 / lut_inv_[a] <= 0.5f * shortest * (1 + 1e-5f)) || lut_origin_[a] != axis_[a][0] ||
          !(static_cast<double>(lut_size_[a] - 1) / lut_inv_[a] >=
            static_cast<double>(axis_[a][n_[a] - 1] - axis_[a][0]) * (1 - 1e-6)))
        return say(error, error_size, "bad lookup of axis %d", a), false;
    }
    const float last_bin = static_cast<float>(lut_size_[a] - 1);
    std::uint32_t below = 0, next = 1;  // interior nodes of lower bins; the next interior node
    for (std::uint32_t b = 0; b < lut_size_[a]; ++b) {
      float split = INFINITY;
      while (next + 1 < n_[a] &&
             detail::axis_bin(axis_[a][next], lut_origin_[a], lut_inv_[a], last_bin) == b) {
        if (split != INFINITY)
          return say(error, error_size, "bin %u of axis %d holds two nodes", b, a), false;
        split = axis_[a][next++];
      }
      const spz_axis_bin& e = lut_[a][b];
      const float position = axis_[a][below];
      const float inverse = n_[a] > 1 && a < static_cast<int>(dims_) ? inverse_[a][below] : 0.0f;
      if (e.node != below * stride[a] || std::memcmp(&e.split, &split, sizeof split) != 0 ||
          std::memcmp(&e.position, &position, sizeof position) != 0 ||
          std::memcmp(&e.inverse, &inverse, sizeof inverse) != 0)
        return say(error, error_size, "axis lookup entry %u of axis %d is wrong", b, a), false;
      below = next - 1;
    }
    lut_at += lut_size_[a];
  }
  {  // The final entry, read as the bin after the last: zeros.
    const spz_axis_bin zeros{};
    if (std::memcmp(static_cast<const spz_axis_bin*>(at[SPZ_SECTION_AXIS_LUT]) + lut_at, &zeros,
                    sizeof zeros) != 0)
      return say(error, error_size, "the axis lookup's final entry is not zeros"), false;
  }
  slots_ = u32(SPZ_SECTION_NODE_SLOTS);
  for (std::uint64_t k = 0; k < nodes; ++k)
    if (slots_[k] != SPZ_OUTSIDE && (slots_[k] % bands != 0 || slots_[k] / bands >= slots))
      return say(error, error_size,
                 "node slot %llu is offset %u: not the start of one of the %llu spectra",
                 static_cast<unsigned long long>(k), slots_[k],
                 static_cast<unsigned long long>(slots)),
             false;
  spectra_ = static_cast<const float*>(at[SPZ_SECTION_SPECTRA]);
  for (std::uint64_t k = 0; k < slots * bands; ++k)
    if (!(spectra_[k] >= 0.0f && spectra_[k] <= h->sample_bound))
      return say(error, error_size, "spectrum %llu, sample %llu is %g: not in [0, sample_bound %g]",
                 static_cast<unsigned long long>(k / bands),
                 static_cast<unsigned long long>(k % bands), static_cast<double>(spectra_[k]),
                 h->sample_bound),
             false;
  bcells_ = u32(SPZ_SECTION_BOUNDARY_CELLS);
  simplices_ = u32(SPZ_SECTION_SIMPLICES);
  bpos_ = f64(SPZ_SECTION_BOUNDARY_POSITIONS);
  bmask_ = u32(SPZ_SECTION_BOUNDARY_MASKS);
  bpick_ = u32(SPZ_SECTION_BOUNDARY_PICKS);
  bvalue_ = static_cast<const float*>(at[SPZ_SECTION_BOUNDARY_VALUES]);
  for (std::uint64_t v = 0; v < nbv; ++v) {
    for (int c = 0; c < 3; ++c)
      if (!detail::finite(bpos_[3 * v + c]))
        return say(error, error_size, "boundary position %llu is not finite",
                   static_cast<unsigned long long>(v)),
               false;
    if ((bpick_[v] & 0xFFFFu) >= bands || (bpick_[v] >> 16) >= bands)
      return say(error, error_size, "boundary pick %llu names a sample beyond the bands",
                 static_cast<unsigned long long>(v)),
             false;
    for (int c = 0; c < 2; ++c) {
      const float x = bvalue_[2 * v + c];
      if (!(x >= 0.0f && x <= h->sample_bound))
        return say(error, error_size, "boundary value %llu is not in [0, sample_bound]",
                   static_cast<unsigned long long>(v)),
               false;
    }
    bool any_one = false;
    for (std::uint32_t w = 0; w < h->mask_words; ++w)
      any_one = any_one || bmask_[v * h->mask_words + w] != 0;
    if (any_one && !(h->sample_bound >= 1))
      return say(error, error_size, "boundary mask %llu holds samples above sample_bound",
                 static_cast<unsigned long long>(v)),
             false;
    const std::uint32_t last = bmask_[(v + 1) * h->mask_words - 1];
    if (bands % 32 != 0 && (last >> (bands % 32)) != 0)
      return say(error, error_size, "boundary mask %llu has bits beyond the bands",
                 static_cast<unsigned long long>(v)),
             false;
  }
  const std::uint32_t corners = reflectance ? 8 : 4;
  for (std::uint64_t s = 0; s < nsimplex * 4; ++s) {
    const std::uint32_t r = simplices_[s];
    if ((r & SPZ_BOUNDARY_BIT) ? (r & ~SPZ_BOUNDARY_BIT) >= nbv : r >= corners)
      return say(error, error_size, "simplex %llu has a bad vertex",
                 static_cast<unsigned long long>(s / 4)),
             false;
  }
  // Boundary cells hold consecutive runs of simplices, in order, each run no longer than
  // max_cell_simplices, together every simplex: a fetch's work is bounded, and the checks below
  // visit each simplex once.
  std::uint64_t next_simplex = 0;
  for (std::uint64_t b = 0; b < nbc; ++b) {
    const std::uint64_t first = bcells_[2 * b], n = bcells_[2 * b + 1];
    if (first != next_simplex || n == 0 || n > h->max_cell_simplices || n > nsimplex - first)
      return say(error, error_size,
                 "boundary cell %llu: simplices %llu..%llu (runs are consecutive, 1 to "
                 "max_cell_simplices %u long, %llu in all)",
                 static_cast<unsigned long long>(b), static_cast<unsigned long long>(first),
                 static_cast<unsigned long long>(first + n), h->max_cell_simplices,
                 static_cast<unsigned long long>(nsimplex)),
             false;
    next_simplex = first + n;
  }
  if (next_simplex != nsimplex)
    return say(error, error_size, "simplices %llu..%llu belong to no boundary cell",
               static_cast<unsigned long long>(next_simplex),
               static_cast<unsigned long long>(nsimplex)),
           false;
  // Cells: each boundary cell named by exactly one cell, in order (as the writer numbers them);
  // none at an axis' last node.
  cells_ = u32(SPZ_SECTION_CELLS);
  std::uint64_t next_boundary = 0;
  for (std::uint64_t c = 0; c < nodes; ++c) {
    const std::uint32_t code = cells_[c];
    const int i[3] = {static_cast<int>(c % n_[0]), static_cast<int>((c / n_[0]) % n_[1]),
                      static_cast<int>(c / stride[2])};
    const bool last = static_cast<std::uint32_t>(i[0]) + 1 == n_[0] ||
                      static_cast<std::uint32_t>(i[1]) + 1 == n_[1] ||
                      (reflectance && static_cast<std::uint32_t>(i[2]) + 1 == n_[2]);
    if (last && code != SPZ_OUTSIDE)
      return say(error, error_size,
                 "the cell code of node %llu, the last of an axis, is not SPZ_OUTSIDE",
                 static_cast<unsigned long long>(c)),
             false;
    if (code == SPZ_OUTSIDE) continue;
    if (code == 0) {
      for (std::uint32_t k = 0; k < corners; ++k)
        if (slot_of_corner(i, k) == SPZ_OUTSIDE)
          return say(error, error_size, "inside cell %llu has a corner without spectrum",
                     static_cast<unsigned long long>(c)),
                 false;
      continue;
    }
    const std::uint32_t b = code & ~SPZ_BOUNDARY_BIT;
    if (!(code & SPZ_BOUNDARY_BIT) || b != next_boundary)
      return say(error, error_size,
                 "cell %llu has code 0x%08x (boundary cells are numbered in cell order)",
                 static_cast<unsigned long long>(c), code),
             false;
    ++next_boundary;
    const std::uint64_t first = bcells_[2 * b], n = bcells_[2 * b + 1];
    for (std::uint64_t s = first * 4; s < (first + n) * 4; ++s)
      if (!(simplices_[s] & SPZ_BOUNDARY_BIT) && slot_of_corner(i, simplices_[s]) == SPZ_OUTSIDE)
        return say(error, error_size, "a simplex of cell %llu has a corner without spectrum",
                   static_cast<unsigned long long>(c)),
               false;
  }
  if (next_boundary != nbc)
    return say(error, error_size, "boundary cells %llu..%llu belong to no cell",
               static_cast<unsigned long long>(next_boundary),
               static_cast<unsigned long long>(nbc)),
           false;
  const int plane_sections[2] = {SPZ_SECTION_LOCUS_PLANES, SPZ_SECTION_SOLID_PLANES};
  for (int s : plane_sections)
    for (std::uint64_t k = 0; k < count[s] / 4; ++k) {
      const double* p = f64(s) + 4 * k;
      const double norm = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      if (!detail::finite(p[3]) || !(std::abs(norm - 1) <= 1e-6))
        return say(error, error_size, "plane %llu of '%s' is not a unit normal and an offset",
                   static_cast<unsigned long long>(k), detail::section_name(s)),
               false;
    }
  locus_ = {f64(SPZ_SECTION_LOCUS_PLANES), locus_planes};
  solid_ = {f64(SPZ_SECTION_SOLID_PLANES), solid_planes};
  band_weights_ = f64(SPZ_SECTION_BAND_WEIGHTS);
  for (std::uint64_t k = 0; k < 3 * std::uint64_t{bands}; ++k)
    if (!detail::finite(band_weights_[k]) || band_weights_[k] < 0)
      return say(error, error_size,
                 "band weight %llu is negative or not finite (colour matching "
                 "functions and illuminants are >= 0)",
                 static_cast<unsigned long long>(k)),
             false;
  for (int k = 0; k < 9; ++k) to_target_f_[k] = static_cast<float>(h->rgb_to_target[k]);
  for (int a = 0; a < 3; ++a)
    fast_[a] = {
        lut_[a],     lut_origin_[a],      lut_inv_[a],     static_cast<float>(lut_size_[a] - 1),
        axis_[a][0], axis_[a][n_[a] - 1], lut_size_[a] - 1};
#if defined(__SSE2__)
  if (reflectance) {
    for (int a = 0; a < 3; ++a) {
      lanes_.lo[a] = fast_[a].lo, lanes_.hi[a] = fast_[a].hi;
      lanes_.origin[a] = fast_[a].origin, lanes_.inv_bin[a] = fast_[a].inv_bin;
      lanes_.last[a] = static_cast<std::int32_t>(lut_size_[a] - 1);
      lanes_.lut_at[a] = static_cast<std::int32_t>(lut_[a] - lut_[0]);
    }
    const std::uint32_t* step = stride_;
    lanes_.far = step[0] + step[1] + step[2];
    float steps = 0;
    direct_ = squared_axes(lanes_.zero_node, steps);
    for (int a = 0; a < 3; ++a) {
      lanes_.steps[a] = steps, lanes_.last_k[a] = steps - 1, lanes_.steps2[a] = steps * steps;
      lanes_.stride[a] = static_cast<float>(step[a]);
    }
    for (std::uint32_t code = 0; code < 8; ++code) {
      // Each axis' rank among the three (ties by axis order), as fast_blend<3> ranks them;
      // the two orders no floats have (f1 > f0, f2 > f1, f0 >= f2) get the axes' own order.
      const std::uint32_t gt01 = code & 1u, gt02 = (code >> 1) & 1u, gt12 = (code >> 2) & 1u;
      std::uint32_t rank[3] = {gt01 + gt02, (1 - gt01) + gt12, (1 - gt02) + (1 - gt12)};
      if (rank[0] == rank[1] || rank[0] == rank[2] || rank[1] == rank[2])
        rank[0] = 0, rank[1] = 1, rank[2] = 2;
      for (std::uint8_t a = 0; a < 3; ++a) lanes_.order[code][rank[a]] = a;
      lanes_.first[code] = step[lanes_.order[code][0]];
      lanes_.second[code] = lanes_.first[code] + step[lanes_.order[code][1]];
    }
  }
#endif
  h_ = h;
  reflectance_ = reflectance;
  bands_ = bands;
  mask_words_ = h->mask_words;
  start_ = static_cast<float>(h->lambda_start);
  step_ = static_cast<float>(h->lambda_step);
  inv_step_ = static_cast<float>(1.0 / h->lambda_step);
  last_ = static_cast<float>(bands - 1);
  for (int l = 0; l < 4; ++l) {
    wave_[0][l] = start_, wave_[1][l] = inv_step_, wave_[2][l] = last_;
    wave_[3][l] = static_cast<float>(bands - 2), wave_[4][l] = step_;
  }
  // A light's samples are its scale times at most sample_bound: below float's largest.
  max_scale_ = static_cast<float>(3.0e38 / h->sample_bound);
  if (!check_meaning(error, error_size)) {
    *this = TableView{};
    return false;
  }
  return true;
}

// What the table means, checked in O(size): every stored spectrum reproduces the colour of its
// position under the band weights (>= 0) to 2e-6 relative; an emission table's samples are no
// larger than a spectrum of X+Y+Z = 1 can hold; the gamuts hold the colours of nodes with spectra.
inline bool TableView::check_meaning(char* error, std::size_t error_size) const noexcept {
  using detail::say;
  const spz_file_header* h = h_;
  const double* w = band_weights_;
  // The target colour of table coordinates: reflectance RGB, emission CIE xy of X+Y+Z = 1.
  auto target = [&](const double p[3]) {
    if (reflectance_) return detail::mul(h->rgb_to_target, {p[0], p[1], p[2]});
    return detail::Vec3{p[0], p[1], 1 - p[0] - p[1]};
  };
  auto check = [&](const detail::Vec3& want, const double got[3], const char* what,
                   unsigned long long index) {
    const double scale = detail::max_abs(want);
    const double err = std::max(std::abs(got[0] - want.x),
                                std::max(std::abs(got[1] - want.y), std::abs(got[2] - want.z)));
    // 2e-6 of the node's own colour (spectra made by `spectralize table`: 1e-7): blends of
    // colours >= 0 then stay within 3 x 2e-6 of theirs, inside SPZ_EXACT_TOLERANCE with the
    // float blend's rounding, whatever the weights.
    if (err <= 2e-6 * scale) return true;
    say(error, error_size,
        "%s %llu does not reproduce the colour of its position (relative error %.2g): a wrong "
        "spectrum, position, band weight or matrix",
        what, index, scale > 0 ? err / scale : err);
    return false;
  };
  const std::uint64_t nx = n_[0], nxy = static_cast<std::uint64_t>(n_[0]) * n_[1];
  const std::uint64_t nodes = nxy * n_[2];
  auto position = [&](std::uint64_t n, double p[3]) {
    p[0] = axis_[0][n % nx], p[1] = axis_[1][(n / nx) % n_[1]], p[2] = axis_[2][n / nxy];
  };
  std::uint64_t with_spectrum = 0;
  for (std::uint64_t n = 0; n < nodes; ++n) {
    const std::uint32_t slot = slots_[n];
    if (slot == SPZ_OUTSIDE) continue;
    double p[3];
    position(n, p);
    const float* s = spectra_ + slot;
    double got[3] = {0, 0, 0};
    for (std::uint32_t k = 0; k < bands_; ++k)
      for (int c = 0; c < 3; ++c) got[c] += s[k] * w[3 * k + c];
    if (!check(target(p), got, "node", static_cast<unsigned long long>(n))) return false;
    ++with_spectrum;
  }
  // Boundary vertices: 0/1 samples but two.
  const std::uint64_t nbv = h->sections[SPZ_SECTION_BOUNDARY_PICKS].count;
  for (std::uint64_t v = 0; v < nbv; ++v) {
    double got[3] = {0, 0, 0};
    const std::uint32_t ref = SPZ_BOUNDARY_BIT | static_cast<std::uint32_t>(v);
    for (std::uint32_t k = 0; k < bands_; ++k) {
      const double value = detail::vertex_value(*this, ref, k);
      for (int c = 0; c < 3; ++c) got[c] += value * w[3 * k + c];
    }
    if (!check(target(bpos_ + 3 * v), got, "boundary vertex", static_cast<unsigned long long>(v)))
      return false;
  }
  // Emission: no sample beyond what a spectrum of X+Y+Z = 1 can hold (1 / the band's X+Y+Z
  // weight, spectra being >= 0), so that a light's scale bounds its samples.
  if (!reflectance_) {
    double most = 0;
    for (std::uint32_t k = 0; k < bands_; ++k) {
      const double sum = w[3 * k] + w[3 * k + 1] + w[3 * k + 2];
      if (sum > 0) most = std::max(most, 1 / sum);
    }
    if (!(h->sample_bound <= most * (1 + 1e-3)))
      return say(error, error_size,
                 "sample_bound %g is more than a spectrum of X+Y+Z = 1 can hold (%g)",
                 h->sample_bound, most),
             false;
  }
  // The gamut holds the colours of nodes with spectra (64 of them, spread over the nodes):
  // planes that reject everything would map every colour.
  const detail::Gamut& gamut = reflectance_ ? solid_ : locus_;
  const std::uint64_t step = std::max<std::uint64_t>(1, with_spectrum / 64);
  std::uint64_t seen = 0;
  for (std::uint64_t n = 0; n < nodes; ++n) {
    if (slots_[n] == SPZ_OUTSIDE || seen++ % step != 0) continue;
    double p[3];
    position(n, p);
    const detail::Vec3 t = target(p);
    // A node on the gamut's boundary lies within its rounding: 1e-6 of the colour.
    const double slack = 1e-6 * detail::max_abs(t);
    for (std::uint64_t f = 0; f < gamut.count; ++f)
      if (detail::dot(gamut.planes + 4 * f, t) > gamut.planes[4 * f + 3] + slack)
        return say(error, error_size,
                   "plane %llu of the %s rejects node %llu, which has a spectrum",
                   static_cast<unsigned long long>(f), reflectance_ ? "solid" : "locus",
                   static_cast<unsigned long long>(n)),
               false;
  }
  return true;
}

inline bool TableView::locate(const double u[3], int i[3], double f[3], bool clamp,
                              bool* moved) const noexcept {
  for (std::uint32_t a = 0; a < dims_; ++a) {
    const float* p = axis_[a];
    const std::uint32_t n = n_[a];
    double v = u[a];
    if (clamp) v = std::min(std::max(v, static_cast<double>(p[0])), static_cast<double>(p[n - 1]));
    if (moved && v != u[a]) *moved = true;
    if (!(v >= p[0] && v <= p[n - 1])) return false;
    std::uint32_t k = lut_[a][detail::axis_bin(static_cast<float>(v), lut_origin_[a], lut_inv_[a],
                                               static_cast<float>(lut_size_[a] - 1))]
                          .node /
                      stride_[a];
    while (k > 0 && v < p[k]) --k;
    while (k + 2 < n && v >= p[k + 1]) ++k;
    i[a] = static_cast<int>(k);
    f[a] = std::min(std::max((v - p[k]) * inverse_[a][k], 0.0), 1.0);
  }
  if (dims_ == 2) i[2] = 0, f[2] = 0;
  return true;
}

// Whether table coordinates v give the colour of u to a relative 1e-6 (in the target colour:
// leaves room for float evaluation within SPZ_EXACT_TOLERANCE), at any magnitude.
inline bool TableView::close_to(const double u[3], const double v[3]) const noexcept {
  detail::Vec3 want, diff;
  if (reflectance_) {
    want = detail::mul(h_->rgb_to_target, {u[0], u[1], u[2]});
    diff = detail::mul(h_->rgb_to_target, {v[0] - u[0], v[1] - u[1], v[2] - u[2]});
  } else {
    want = {u[0], u[1], 1 - u[0] - u[1]};
    diff = {v[0] - u[0], v[1] - u[1], -(v[0] - u[0]) - (v[1] - u[1])};
  }
  return detail::max_abs(diff) <= 1e-6 * detail::max_abs(want);
}

SPZ_COLD inline bool TableView::boundary_of_node(std::uint32_t code, std::uint32_t node,
                                                 const double u[3], Spectrum& s) const noexcept {
  const int i[3] = {static_cast<int>(node % n_[0]), static_cast<int>((node / n_[0]) % n_[1]),
                    static_cast<int>(node / stride_[2])};
  return boundary_blend(code & ~SPZ_BOUNDARY_BIT, i, u, s, false, nullptr);
}

SPZ_COLD inline bool TableView::boundary_blend(std::uint32_t b, const int i[3], const double u[3],
                                               Spectrum& s, bool nearest,
                                               bool* reproduced) const noexcept {
  const std::uint32_t first = bcells_[2 * b], count = bcells_[2 * b + 1];
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = axis_[a][i[a]];
    hi[a] = a < static_cast<int>(dims_) ? axis_[a][i[a] + 1] : lo[a];
  }
  auto vertices = [&](const std::uint32_t* r, double p[4][3]) {
    for (int v = 0; v < 4; ++v) {
      if (r[v] & SPZ_BOUNDARY_BIT) {
        const double* q = bpos_ + 3 * static_cast<std::size_t>(r[v] & ~SPZ_BOUNDARY_BIT);
        p[v][0] = q[0], p[v][1] = q[1], p[v][2] = q[2];
      } else {
        for (int a = 0; a < 3; ++a) p[v][a] = (r[v] >> a) & 1u ? hi[a] : lo[a];
      }
    }
  };
  double best = -1e300, best_w[4] = {0, 0, 0, 0}, best_p[4][3] = {};
  const std::uint32_t* chosen = nullptr;
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t* r = simplices_ + 4 * (static_cast<std::size_t>(first) + k);
    double p[4][3];
    vertices(r, p);
    // Barycentric weights relative to the vertex nearest u: near black (a vertex of the solid)
    // a tiny colour keeps its own relative precision.
    int o = 0;
    double nearest_d = 1e300;
    for (int v = 0; v <= static_cast<int>(dims_); ++v) {
      const double d0 = u[0] - p[v][0], d1 = u[1] - p[v][1];
      const double d2 = dims_ == 3 ? u[2] - p[v][2] : 0.0;
      const double d = d0 * d0 + d1 * d1 + d2 * d2;
      if (d < nearest_d) nearest_d = d, o = v;
    }
    // Zeroed: with two dimensions the third entry is never read, which GCC 16 cannot see.
    int others[3] = {0, 0, 0}, m = 0;
    for (int v = 0; v <= static_cast<int>(dims_); ++v)
      if (v != o) others[m++] = v;
    double w[4] = {0, 0, 0, 0};
    const double d[3] = {u[0] - p[o][0], u[1] - p[o][1], dims_ == 3 ? u[2] - p[o][2] : 0.0};
    if (dims_ == 3) {
      double e[3][3];
      for (int v = 0; v < 3; ++v)
        for (int a = 0; a < 3; ++a) e[v][a] = p[others[v]][a] - p[o][a];
      // Cramer: each weight = det(e with its column replaced by d) / det(e).
      auto det3 = [](const double* a, const double* bb, const double* c) {
        return a[0] * (bb[1] * c[2] - bb[2] * c[1]) - a[1] * (bb[0] * c[2] - bb[2] * c[0]) +
               a[2] * (bb[0] * c[1] - bb[1] * c[0]);
      };
      const double D = det3(e[0], e[1], e[2]);
      if (!(D != 0)) continue;
      w[others[0]] = det3(d, e[1], e[2]) / D;
      w[others[1]] = det3(e[0], d, e[2]) / D;
      w[others[2]] = det3(e[0], e[1], d) / D;
    } else {
      const double a = p[others[0]][0] - p[o][0], bb = p[others[1]][0] - p[o][0];
      const double c = p[others[0]][1] - p[o][1], dd = p[others[1]][1] - p[o][1];
      const double D = a * dd - bb * c;
      if (!(D != 0)) continue;
      w[others[0]] = (d[0] * dd - bb * d[1]) / D;
      w[others[1]] = (a * d[1] - c * d[0]) / D;
    }
    double rest = 0;
    for (int v = 0; v <= static_cast<int>(dims_); ++v)
      if (v != o) rest += w[v];
    w[o] = 1 - rest;
    double worst = 1;
    for (int v = 0; v <= static_cast<int>(dims_); ++v) worst = std::min(worst, w[v]);
    if (worst > best) {
      best = worst, chosen = r;
      for (int v = 0; v < 4; ++v) {
        best_w[v] = w[v];
        for (int a = 0; a < 3; ++a) best_p[v][a] = p[v][a];
      }
      if (worst >= 0) break;
    }
  }
  if (!chosen) return false;
  // The colour the clamped weights give: the colour asked, to rounding, or another one.
  auto blended = [&](const double w[4], const double p[4][3], double out[3]) {
    double sum = 0;
    for (int v = 0; v < 4; ++v) sum += std::max(w[v], 0.0);
    out[0] = out[1] = out[2] = 0;
    for (int v = 0; v < 4; ++v)
      for (int a = 0; a < 3; ++a) out[a] += std::max(w[v], 0.0) / sum * p[v][a];
    if (dims_ == 2) out[2] = u[2];
  };
  double got[3];
  blended(best_w, best_p, got);
  bool holds = best >= 0 || close_to(u, got);
  if (!holds) {
    if (!nearest) return false;
    // Within rounding of the gamut but outside the cell's simplices (float input on the
    // boundary, a colour mapped just short of it): the blend of the nearest point of the
    // nearest simplex, a colour other than the one asked.
    double nearest_dist = 1e300;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t* r = simplices_ + 4 * (static_cast<std::size_t>(first) + k);
      double p[4][3], w[4];
      vertices(r, p);
      const double x[3] = {u[0], u[1], dims_ == 3 ? u[2] : p[0][2]};
      const double dist = detail::closest_in_simplex(p, static_cast<int>(dims_), x, w);
      if (dist < nearest_dist) {
        nearest_dist = dist, chosen = r;
        for (int v = 0; v < 4; ++v) {
          best_w[v] = w[v];
          for (int a = 0; a < 3; ++a) best_p[v][a] = p[v][a];
        }
      }
    }
    blended(best_w, best_p, got);
    holds = close_to(u, got);
  }
  if (reproduced && !holds) *reproduced = false;
  double sum = 0;
  for (double& w : best_w) sum += (w = std::max(w, 0.0));
  s.flags &= ~1u;
  for (int v = 0; v < 4; ++v) {
    const std::uint32_t r = chosen[v];
    if (r & SPZ_BOUNDARY_BIT) {
      s.vertex[v] = r;
      s.flags |= 1u;
    } else {
      s.vertex[v] = slot_of_corner(i, r);
    }
    s.weight[v] = static_cast<float>(best_w[v] / sum);
  }
  return true;
}

inline bool TableView::cell_blend(const int i[3], const double f[3], const double u[3], Spectrum& s,
                                  bool nearest, bool* reproduced) const noexcept {
  const std::uint32_t code =
      cells_[static_cast<std::uint32_t>(i[0]) + stride_[1] * static_cast<std::uint32_t>(i[1]) +
             stride_[2] * static_cast<std::uint32_t>(i[2])];
  if (code == 0) {
    // Kuhn's simplices: from the lower corner along the axes in decreasing order of the
    // fractional coordinates; the weights are the gaps between them.
    int order[3] = {0, 1, 2};
    if (dims_ == 2) {
      if (f[1] > f[0]) order[0] = 1, order[1] = 0;
    } else {
      if (f[order[1]] > f[order[0]]) std::swap(order[0], order[1]);
      if (f[order[2]] > f[order[1]]) std::swap(order[1], order[2]);
      if (f[order[1]] > f[order[0]]) std::swap(order[0], order[1]);
    }
    std::uint32_t corner = 0;
    double prev = 1;
    s.flags &= ~1u;
    for (std::uint32_t k = 0; k <= dims_; ++k) {
      const double fk = k < dims_ ? f[order[k]] : 0.0;
      s.vertex[k] = slot_of_corner(i, corner);
      s.weight[k] = static_cast<float>(prev - fk);
      prev = fk;
      if (k < dims_) corner |= 1u << order[k];
    }
    if (dims_ == 2) s.vertex[3] = s.vertex[0], s.weight[3] = 0;
    return true;
  }
  if (code == SPZ_OUTSIDE) return false;
  return boundary_blend(code & ~SPZ_BOUNDARY_BIT, i, u, s, nearest, reproduced);
}

// The lookup of fetch(): float arithmetic, one interval step after the bin, Kuhn weights in
// float; boundary cells in double (boundary_blend).
template <int dims>
inline bool TableView::fast_blend(const float u[3], Spectrum& s) const noexcept {
  std::uint32_t base = 0;  // the cell's lowest node: the axes' offsets added (rt_format.h)
  float f[3] = {0, 0, 0};
  bool inside = true;
  for (int a = 0; a < dims; ++a) {
    const AxisFast& x = fast_[a];
    const float v = u[a];
    inside &= (v >= x.lo) & (v <= x.hi);  // false for NaN
#if defined(__SSE2__)
    // The bin clamped after SSE's defined conversion (NaN and any float out of int32 range
    // give 0x80000000): the same bin as axis_bin for every v >= origin, a valid one for others.
    const std::uint32_t bin = std::min(
        static_cast<std::uint32_t>(_mm_cvttss_si32(_mm_set_ss((v - x.origin) * x.inv_bin))),
        x.last);
#else
    const std::uint32_t bin = detail::axis_bin(v, x.origin, x.inv_bin, x.last_bin);
#endif
    // One step: the bin, or the next when v is at or above the node inside it (the final
    // entry of the lookup section makes the next one readable for the last bin).
    const spz_axis_bin* e = x.lut + bin;
    e += v >= e->split;
    base += e->node;
    // v >= position for v inside (the lookup's invariant): only rounding can pass 1.
    f[a] = std::min((v - e->position) * e->inverse, 1.0f);
  }
  const std::uint32_t nx = n_[0], nxy = stride_[2];
  const std::uint32_t code = cells_[base];
  if (!inside | (code != 0)) {  // one branch for the common case
    if (!inside || code == SPZ_OUTSIDE) return false;
    const double du[3] = {u[0], u[1], dims == 3 ? u[2] : 0.0};
    return boundary_of_node(code, base, du, s);
  }
  // Kuhn: the axes in decreasing order of their fractions; the weights are the gaps.
  s.flags &= ~1u;
  if constexpr (dims == 2) {
    const bool xy = f[0] >= f[1];
    const float hi = xy ? f[0] : f[1], lo = xy ? f[1] : f[0];
    s.vertex[0] = s.vertex[3] = slots_[base];
    s.vertex[1] = slots_[base + (xy ? 1 : nx)];
    s.vertex[2] = slots_[base + 1 + nx];
    s.weight[0] = 1 - hi, s.weight[1] = hi - lo, s.weight[2] = lo, s.weight[3] = 0;
    return true;
  } else {
    // Without branches (the order of noisy texels' fractions is unpredictable): each axis'
    // rank among the three (ties by axis order), the walk's first and second steps from the
    // ranks, the weights from max, middle and min.
    const std::uint32_t gt01 = f[1] > f[0], gt02 = f[2] > f[0], gt12 = f[2] > f[1];
    const std::uint32_t r0 = gt01 + gt02, r1 = (1 - gt01) + gt12, r2 = (1 - gt02) + (1 - gt12);
    const std::uint32_t first = (r0 == 0) * 1 + (r1 == 0) * nx + (r2 == 0) * nxy;
    const std::uint32_t second = (r0 == 1) * 1 + (r1 == 1) * nx + (r2 == 1) * nxy;
    // hi >= mid >= lo exactly (a sorting network, not a sum that rounds): every weight below
    // is the difference of two ordered floats, so >= 0 bit for bit.
    const float hi = std::max(std::max(f[0], f[1]), f[2]);
    const float lo = std::min(std::min(f[0], f[1]), f[2]);
    const float mid = std::max(std::min(f[0], f[1]), std::min(std::max(f[0], f[1]), f[2]));
    s.vertex[0] = slots_[base];
    s.vertex[1] = slots_[base + first];
    s.vertex[2] = slots_[base + first + second];
    s.vertex[3] = slots_[base + 1 + nx + nxy];
    s.weight[0] = 1 - hi;
    s.weight[1] = hi - mid;
    s.weight[2] = mid - lo;
    s.weight[3] = lo;
    return true;
  }
}

#if defined(__SSE2__)
inline bool TableView::squared_axes(std::uint32_t& zero_node, float& steps) const noexcept {
  std::uint32_t common = 0;
  std::uint64_t offset = 0, reach = 0;
  for (int a = 0; a < 3; ++a) {
    const float* x = axis_[a];
    std::uint32_t j = 0;
    while (j < n_[a] && x[j] < 0) ++j;
    if (j + 1 >= n_[a] || x[j] != 0 || !(x[j + 1] > 0)) return false;
    const double s = std::round(1 / std::sqrt(static_cast<double>(x[j + 1])));
    if (!(s >= 1 && s <= 4096) || (common && s != common)) return false;
    common = static_cast<std::uint32_t>(s);
    if (j + common >= n_[a]) return false;
    for (std::uint32_t k = 0; k <= common; ++k) {
      const double r = static_cast<double>(k) / common;
      if (x[j + k] != static_cast<float>(r * r)) return false;
    }
    offset += j * stride_[a];
    reach += (common - 1) * stride_[a];
  }
  // The offsets are summed in float: exact below 2^24.
  if (offset + reach >= (1u << 24)) return false;
  zero_node = static_cast<std::uint32_t>(offset);
  steps = static_cast<float>(common);
  return true;
}

// fast_blend<3> with the three axes in SSE lanes: the same cells, vertices and weights.
template <bool kBoundary>
inline bool TableView::fast_blend_sse(const float rgb[3], Spectrum& s) const noexcept {
  const Lanes& L = lanes_;
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 v = _mm_movelh_ps(_mm_loadl_pi(zero, reinterpret_cast<const __m64*>(rgb)),
                                 _mm_load_ss(rgb + 2));  // r, g, b, 0
  __m128 f;
  std::uint32_t base;
  bool inside = true;
  if (direct_ && _mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmple_ps(v, one))) == 0xF) {
    // [0, 1] (NaN is not): the interval below v is k = floor(steps * sqrt(v)) but for
    // rounding at a node, where f, clamped, is 0 or 1 of the neighbour: the same point.
    const __m128 k = _mm_cvtepi32_ps(_mm_cvttps_epi32(
        _mm_min_ps(_mm_mul_ps(_mm_sqrt_ps(v), _mm_load_ps(L.steps)), _mm_load_ps(L.last_k))));
    // f = (v - (k / steps)^2) / ((2k + 1) / steps^2); k^2 and 2k + 1 are exact in float.
    f = _mm_div_ps(_mm_sub_ps(_mm_mul_ps(v, _mm_load_ps(L.steps2)), _mm_mul_ps(k, k)),
                   _mm_add_ps(_mm_add_ps(k, k), one));
    f = _mm_min_ps(_mm_max_ps(f, zero), one);
    // The cell's lowest node: black's plus k times each stride (exact in float, squared_axes).
    __m128 o = _mm_mul_ps(k, _mm_load_ps(L.stride));
    o = _mm_add_ps(o, _mm_movehl_ps(o, o));
    o = _mm_add_ss(o, _mm_shuffle_ps(o, o, 0x55));
    base = L.zero_node + static_cast<std::uint32_t>(_mm_cvttss_si32(o));
  } else {
    // Inside the grid (NaN is not); lane 3's 0 is inside [0, 0].
    inside = _mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(v, _mm_load_ps(L.lo)),
                                        _mm_cmple_ps(v, _mm_load_ps(L.hi)))) == 0xF;
    // The bins of detail::axis_bin for every v up to the grid's end, clamped after the cast:
    // SSE's conversion is defined for any float (NaN and beyond int32: 0x80000000, bin 0).
    const __m128i last = _mm_load_si128(reinterpret_cast<const __m128i*>(L.last));
    const __m128i raw =
        _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(v, _mm_load_ps(L.origin)), _mm_load_ps(L.inv_bin)));
    const __m128i above = _mm_cmpgt_epi32(raw, last);
    const __m128i top = _mm_or_si128(_mm_and_si128(above, last), _mm_andnot_si128(above, raw));
    const __m128i bin =
        _mm_add_epi32(_mm_andnot_si128(_mm_cmplt_epi32(top, _mm_setzero_si128()), top),
                      _mm_load_si128(reinterpret_cast<const __m128i*>(L.lut_at)));
    // Each axis' bin and the next one (spz_axis_bin: node, split, position, inverse), in lanes:
    // the node offset, position and inverse below the split, or above it (the next bin's),
    // chosen by v >= split (a true compare is all bits).
    const spz_axis_bin* lut = lut_[0];
    const spz_axis_bin* b0 = lut + _mm_cvtsi128_si32(bin);
    const spz_axis_bin* b1 = lut + _mm_cvtsi128_si32(_mm_shuffle_epi32(bin, 0x55));
    const spz_axis_bin* b2 = lut + _mm_cvtsi128_si32(_mm_shuffle_epi32(bin, 0xAA));
    auto load = [](const spz_axis_bin* b) {  // 16 bytes; a view's data is only 8-byte aligned
      return _mm_loadu_ps(reinterpret_cast<const float*>(b));
    };
    __m128 e0 = load(b0), e1 = load(b1), e2 = load(b2), e3 = zero;
    __m128 n0 = load(b0 + 1), n1 = load(b1 + 1), n2 = load(b2 + 1), n3 = zero;
    _MM_TRANSPOSE4_PS(e0, e1, e2, e3);  // node offsets, splits, positions, inverses
    _MM_TRANSPOSE4_PS(n0, n1, n2, n3);  // the next bins'
    const __m128 upper = _mm_cmpge_ps(v, e1);
    const __m128i k = _mm_castps_si128(_mm_or_ps(_mm_and_ps(upper, n0), _mm_andnot_ps(upper, e0)));
    const __m128 p = _mm_or_ps(_mm_and_ps(upper, n2), _mm_andnot_ps(upper, e2));
    const __m128 inv = _mm_or_ps(_mm_and_ps(upper, n3), _mm_andnot_ps(upper, e3));
    // The cell's lowest node: the three offsets added (lane 3 is 0).
    const __m128i k2 = _mm_add_epi32(k, _mm_shuffle_epi32(k, _MM_SHUFFLE(1, 0, 3, 2)));
    base = static_cast<std::uint32_t>(
        _mm_cvtsi128_si32(_mm_add_epi32(k2, _mm_shuffle_epi32(k2, 0x55))));
    // In [0, 1] for v inside (v >= p, the lookup's invariant) but for rounding above 1, which
    // the first weight absorbs below (off the path to the vertices).
    f = _mm_mul_ps(_mm_sub_ps(v, p), inv);
  }
  const std::uint32_t code = cells_[base];
  if (!inside | (code != 0)) {  // one branch for the common case
    if (!kBoundary || !inside || code == SPZ_OUTSIDE) return false;
    const double du[3] = {rgb[0], rgb[1], rgb[2]};
    return boundary_of_node(code, base, du, s);
  }
  // Kuhn: the order of the fractions (f1 > f0, f2 > f0, f2 > f1 in bits 0-2), its walk and
  // the weights, the gaps between the sorted fractions (ordered floats: >= 0 bit for bit).
  const int order = _mm_movemask_ps(_mm_cmpgt_ps(_mm_shuffle_ps(f, f, _MM_SHUFFLE(3, 2, 2, 1)),
                                                 _mm_shuffle_ps(f, f, _MM_SHUFFLE(3, 1, 0, 0)))) &
                    7;
  alignas(16) float fa[4];
  _mm_store_ps(fa, f);
  const std::uint8_t* by = L.order[order];
  const float hi = fa[by[0]], mid = fa[by[1]], lo = fa[by[2]];
  s.flags &= ~1u;
  s.vertex[0] = slots_[base];
  s.vertex[1] = slots_[base + L.first[order]];
  s.vertex[2] = slots_[base + L.second[order]];
  s.vertex[3] = slots_[base + L.far];
  s.weight[0] = std::max(1 - hi, 0.0f);
  s.weight[1] = hi - mid;
  s.weight[2] = mid - lo;
  s.weight[3] = lo;
  return true;
}
#endif

inline bool TableView::blend(const double u[3], Spectrum& s, bool nearest,
                             bool* reproduced) const noexcept {
  int i[3] = {0, 0, 0};  // set by locate(); initialised for GCC's -Wmaybe-uninitialized
  double f[3] = {0, 0, 0};
  bool moved = false;
  if (!locate(u, i, f, nearest, &moved)) return false;
  if (moved && reproduced) *reproduced = false;  // a colour beyond the grid, clamped onto it
  if (cell_blend(i, f, u, s, false, reproduced)) return true;
  if (!nearest) return false;
  // A point on a face between cells (the solid's white vertex is a corner of cells outside
  // it) belongs to the neighbours that touch it too; else the nearest simplex of its cell.
  for (std::uint32_t c = 1; c < (1u << dims_); ++c) {
    int j[3] = {i[0], i[1], i[2]};
    double g[3] = {f[0], f[1], f[2]};
    bool touches = true;
    for (std::uint32_t a = 0; a < dims_ && touches; ++a) {
      if (!((c >> a) & 1u)) continue;
      if (f[a] <= 1e-9 && i[a] > 0) {
        --j[a], g[a] = 1;
      } else if (f[a] >= 1 - 1e-9 && static_cast<std::uint32_t>(i[a]) + 2 < n_[a]) {
        ++j[a], g[a] = 0;
      } else {
        touches = false;
      }
    }
    if (touches && cell_blend(j, g, u, s, false, reproduced)) return true;
  }
  return cell_blend(i, f, u, s, true, reproduced);
}

SPZ_HOT_INLINE int TableView::fetch(const float rgb[3], Spectrum& s) const noexcept {
  if (!h_) {  // an empty view: the zero spectrum of no table
    s.table = nullptr;
    s.flags = 0;
    zero(s);
    return SPZ_INVALID;
  }
  if (reflectance_) {
    if (fast_reflectance<true>(rgb, s)) return SPZ_EXACT;
  } else {
    s.table = this;
    s.flags = 0;
    const float* m = to_target_f_;
    const float X = m[0] * rgb[0] + m[1] * rgb[1] + m[2] * rgb[2];
    const float Y = m[3] * rgb[0] + m[4] * rgb[1] + m[5] * rgb[2];
    const float Z = m[6] * rgb[0] + m[7] * rgb[1] + m[8] * rgb[2];
    const float S = X + Y + Z;
    // Its samples are S times at most sample_bound: finite (false for NaN and infinities).
    if (S >= static_cast<float>(kDarkest) && S <= max_scale_) {
      const float u[3] = {X / S, Y / S, 0};
      s.scale = S;
      if (fast_blend<2>(u, s)) return SPZ_EXACT;
    }
  }
  return slow_fetch(rgb, s);
}

template <bool kBoundary>
SPZ_HOT_INLINE bool TableView::fast_reflectance(const float rgb[3], Spectrum& s) const noexcept {
  s.table = this;
  s.flags = 2u;
  s.scale = 1;
  // Colours darker than kDarkest go the slow way (false for NaN too).
  const float top = std::max(std::max(rgb[0], rgb[1]), rgb[2]);
  if (!(top >= static_cast<float>(kDarkest))) return false;
#if defined(__SSE2__)
  return fast_blend_sse<kBoundary>(rgb, s);
#else
  return fast_blend<3>(rgb, s);
#endif
}

SPZ_HOT_INLINE int TableView::fetch_eval4(const float rgb[3], const float lambda_nm[4],
                                          float out[4], Spectrum* keep) const noexcept {
  if (reflectance_) {
    // fetch()'s common path with a spectrum whose address is never taken (boundary cells go
    // the full way): the compiler keeps it in registers from the lookup to the values, where
    // fetch() hands it through memory.
    Spectrum s;
    if (fast_reflectance<false>(rgb, s)) {
      eval4(s, lambda_nm, out);
      if (keep) *keep = s;
      return SPZ_EXACT;
    }
  }
  Spectrum s;
  const int status = fetch(rgb, s);
  eval4(s, lambda_nm, out);
  if (keep) *keep = s;
  return status;
}

inline int TableView::map_target(detail::Vec3& t) const noexcept {
  // The CLI's rule (docs/DESIGN.md §5), step by step in double precision.
  const detail::Gamut& gamut = reflectance_ ? solid_ : locus_;
  if (gamut.contains(t)) return SPZ_EXACT;
  const detail::Vec3 requested = t;
  auto move_toward = [&](const detail::Gamut& g, double margin, const detail::Vec3& anchor) {
    if (g.contains(t)) return;
    const double sb = g.max_step(anchor, t);
    const double k = sb >= 2 * margin ? sb - margin : 0.5 * sb;
    t = {anchor.x + k * (t.x - anchor.x), anchor.y + k * (t.y - anchor.y),
         anchor.z + k * (t.z - anchor.z)};
  };
  const double* lw = h_->locus_white;
  if (!locus_.contains(t)) {
    const double y = t.y / lw[1];
    move_toward(locus_, h_->locus_margin, {y * lw[0], y * lw[1], y * lw[2]});
  }
  if (reflectance_ && !solid_.contains(t)) {
    if (t.y > 1) move_toward(solid_, h_->solid_margin, {0, 0, 0});
    if (!solid_.contains(t)) {
      const double* sw = h_->solid_white;
      move_toward(solid_, h_->solid_margin, {t.y * sw[0], t.y * sw[1], t.y * sw[2]});
    }
  }
  const detail::Vec3 d{t.x - requested.x, t.y - requested.y, t.z - requested.z};
  const double scale = detail::max_abs(requested);
  if (scale > 0 && detail::max_abs(d) / scale <= h_->snap_tolerance) return SPZ_EXACT;
  return SPZ_MAPPED;
}

SPZ_COLD inline int TableView::slow_fetch(const float rgb[3], Spectrum& s) const noexcept {
  const detail::Vec3 c{rgb[0], rgb[1], rgb[2]};
  detail::Vec3 t = detail::mul(h_->rgb_to_target, c);
  zero(s);
  if (!detail::finite(t.x) || !detail::finite(t.y) || !detail::finite(t.z)) return SPZ_INVALID;
  if (t.x == 0 && t.y == 0 && t.z == 0) return SPZ_EXACT;  // black
  if (t.y < 0) return SPZ_NEGATIVE;
  // So dark that a float spectrum cannot reproduce it to SPZ_EXACT_TOLERANCE (its samples would
  // be denormal): black, and said to be another colour.
  if (detail::max_abs(t) < kDarkest) return SPZ_MAPPED;
  const int status = map_target(t);
  if (!(t.y > 0)) return SPZ_MAPPED;  // a colour of zero luminance maps to black
  double u[3];
  if (reflectance_) {
    const detail::Vec3 r = detail::mul(h_->target_to_rgb, t);
    u[0] = r.x, u[1] = r.y, u[2] = r.z;
    s.scale = 1;
  } else {
    const double S = t.x + t.y + t.z;
    if (!(S <= max_scale_)) {  // a light too bright for its spectrum to be finite in float
      zero(s);
      return SPZ_INVALID;
    }
    u[0] = t.x / S, u[1] = t.y / S, u[2] = 0;
    s.scale = static_cast<float>(S);
  }
  // Inside the gamut (within its rounding, or mapped 1e-4 short of its boundary): the nearest
  // simplex of the cell holds it. The spectrum of another colour than the one asked (beyond
  // rounding: the nearest point of a simplex, a clamped position) is a mapping, and said so;
  // none at all would be a table without the colours it claims to hold.
  bool reproduced = true;
  if (!blend(u, s, true, &reproduced)) {
    zero(s);
    return SPZ_INVALID;
  }
  return status == SPZ_EXACT && !reproduced ? SPZ_MAPPED : status;
}

inline int TableView::map_into_gamut(const double rgb[3], double mapped[3]) const noexcept {
  const detail::Vec3 c{rgb[0], rgb[1], rgb[2]};
  detail::Vec3 t = detail::mul(h_->rgb_to_target, c);
  mapped[0] = mapped[1] = mapped[2] = 0;
  if (!detail::finite(t.x) || !detail::finite(t.y) || !detail::finite(t.z)) return SPZ_INVALID;
  if (t.x == 0 && t.y == 0 && t.z == 0) return SPZ_EXACT;
  if (t.y < 0) return SPZ_NEGATIVE;
  const int status = map_target(t);
  if (!(t.y > 0)) return SPZ_MAPPED;
  const detail::Vec3 r = detail::mul(h_->target_to_rgb, t);
  mapped[0] = r.x, mapped[1] = r.y, mapped[2] = r.z;
  return status;
}

inline std::size_t fetch_array(const TableView& t, const float* rgb, std::size_t n,
                               const float* lambda_nm, std::size_t m, float* out, int* statuses,
                               std::size_t counts[4]) noexcept {
  const std::size_t row = lambda_nm ? m : t.bands();
  if (counts) counts[0] = counts[1] = counts[2] = counts[3] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Spectrum s{};
    const int status = t.fetch(rgb + 3 * i, s);
    if (statuses) statuses[i] = status;
    if (counts) ++counts[status >= 0 ? status : status == SPZ_INVALID ? 2 : 3];
    float* o = out + i * row;
    if (!lambda_nm) {
      samples(s, o);
      continue;
    }
    std::size_t k = 0;
    for (; k + 4 <= m; k += 4) eval4(s, lambda_nm + k, o + k);
    for (; k < m; ++k) o[k] = eval(s, lambda_nm[k]);
  }
  return row;
}

inline const TableView& TableView::none() noexcept {
  static constexpr TableView empty{};  // constant-initialised: no guard, no runtime library
  return empty;
}

// --- Table ---

inline bool Table::load(const char* path, char* error, std::size_t error_size) noexcept {
  release();
  char reason[400] = "";
  auto fail = [&](const char* why) {
    detail::say(error, error_size, "%s: %s", path ? path : "(null)", why);
    return false;
  };
  if (!path) return fail("no path given");
#if defined(__unix__) || defined(__APPLE__)
  struct stat st;
  if (::stat(path, &st) != 0) return fail(std::strerror(errno));
  if (S_ISDIR(st.st_mode)) return fail("is a directory, not a table file");
  if (!S_ISREG(st.st_mode)) return fail("not a regular file");
#endif
  std::FILE* file = std::fopen(path, "rb");
  if (!file) return fail(std::strerror(errno));
  struct Closer {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{file};
  long length = -1;
  if (std::fseek(file, 0, SEEK_END) == 0) length = std::ftell(file);
  if (length < 0 || std::fseek(file, 0, SEEK_SET) != 0) return fail("cannot read its size");
  const std::size_t size = static_cast<std::size_t>(length);
  // The header first: a file that is no table of this version, or not of the size it says,
  // is refused before anything else is read.
  alignas(8) unsigned char head[SPZ_HEADER_SIZE];
  if (size < SPZ_HEADER_SIZE) {
    std::snprintf(reason, sizeof reason,
                  "truncated: %zu bytes, a table has a %u-byte header at least", size,
                  SPZ_HEADER_SIZE);
    return fail(reason);
  }
  if (std::fread(head, 1, SPZ_HEADER_SIZE, file) != SPZ_HEADER_SIZE)
    return fail("cannot read its header");
  if (!detail::check_header_start(reinterpret_cast<const spz_file_header*>(head), size, reason,
                                  sizeof reason))
    return fail(reason);
  constexpr std::size_t kMax = std::size_t{1} << 30;
  if (size > kMax) return fail("larger than 1 GiB: not a table this evaluator loads");
  // C's aligned_alloc (a multiple of the alignment): the C library needs nothing but libc.
  block_ = static_cast<unsigned char*>(std::aligned_alloc(64, (kBytesAt + size + 63) / 64 * 64));
  if (!block_) return fail("out of memory");
  unsigned char* data = block_ + kBytesAt;
  std::memcpy(data, head, SPZ_HEADER_SIZE);
  const std::size_t rest = size - SPZ_HEADER_SIZE;
  const std::size_t got = rest ? std::fread(data + SPZ_HEADER_SIZE, 1, rest, file) : 0;
  if (got != rest || std::ferror(file) != 0) {
    release();
    return fail("cannot read it whole");
  }
  view_ = new (block_) TableView();
  if (!view_->open(data, size, reason, sizeof reason)) {
    release();
    return fail(reason);
  }
  return true;
}

}  // namespace spz

/// A loaded table of the C API.
struct spz_table {
  spz::Table table;
};

// rt.hpp has been read whole (rt.h may now include it again for the C definitions below).
#define SPECTRALIZE_RT_HPP_DONE
#endif  // SPECTRALIZE_RT_HPP

// The C API's definitions, in the one translation unit that defines
// SPECTRALIZE_RT_IMPLEMENTATION (outside the include guard: rt.hpp may have been included
// before without it).
#if defined(SPECTRALIZE_RT_IMPLEMENTATION) && !defined(SPECTRALIZE_RT_C_DEFINED)
#define SPECTRALIZE_RT_C_DEFINED
extern "C" {

spz_table* spz_table_load(const char* path, char* error, size_t error_size) {
  // malloc and placement new: the compiled C library needs nothing of the C++ runtime.
  void* memory = std::malloc(sizeof(spz_table));
  spz_table* t = memory ? new (memory) spz_table : nullptr;
  if (!t) {
    spz::detail::say(error, error_size, "%s: out of memory", path ? path : "(null)");
    return nullptr;
  }
  if (!t->table.load(path, error, error_size)) {
    t->~spz_table();
    std::free(t);
    return nullptr;
  }
  return t;
}

void spz_table_free(spz_table* table) {
  if (!table) return;
  table->~spz_table();
  std::free(table);
}

// No table fetches as the empty view: SPZ_INVALID and the zero spectrum.
int spz_fetch(const spz_table* table, const float rgb[3], spz_spectrum* out) {
  return (table ? table->table.view() : spz::TableView::none()).fetch(rgb, *out);
}

int spz_fetch_eval4(const spz_table* table, const float rgb[3], const float lambda_nm[4],
                    float out[4], spz_spectrum* keep) {
  return (table ? table->table.view() : spz::TableView::none())
      .fetch_eval4(rgb, lambda_nm, out, keep);
}

float spz_eval(const spz_spectrum* s, float lambda_nm) {
  return spz::eval(*s, lambda_nm);
}

void spz_eval4(const spz_spectrum* s, const float lambda_nm[4], float out[4]) {
  spz::eval4(*s, lambda_nm, out);
}

void spz_samples(const spz_spectrum* s, float* out) {
  spz::samples(*s, out);
}

size_t spz_samples_n(const spz_spectrum* s, float* out, size_t capacity) {
  return spz::samples(*s, out, capacity);
}

size_t spz_spectrum_bands(const spz_spectrum* s) {
  return spz::bands(*s);
}

float spz_spectrum_max(const spz_spectrum* s) {
  return spz::max_value(*s);
}

size_t spz_fetch_array(const spz_table* table, const float* rgb, size_t n, const float* lambda_nm,
                       size_t m, float* out, int* statuses, size_t counts[4]) {
  return spz::fetch_array(table ? table->table.view() : spz::TableView::none(), rgb, n, lambda_nm,
                          m, out, statuses, counts);
}

size_t spz_table_bands(const spz_table* table) {
  return table ? table->table.view().bands() : 0;
}

void spz_table_wavelengths(const spz_table* table, float* start_nm, float* step_nm) {
  if (start_nm) *start_nm = table ? table->table.view().lambda_start() : 0.0f;
  if (step_nm) *step_nm = table ? table->table.view().lambda_step() : 0.0f;
}

int spz_table_mode(const spz_table* table) {
  return !table ? -1 : table->table.view().reflectance() ? 1 : 0;
}

const char* spz_table_colorspace(const spz_table* table) {
  return table ? table->table.view().header().colorspace : "";
}

void spz_table_rgb_to_xyz(const spz_table* table, double matrix[9]) {
  for (int k = 0; k < 9; ++k) matrix[k] = table ? table->table.view().header().rgb_to_xyz[k] : 0;
}

void spz_table_rgb_to_target(const spz_table* table, double matrix[9]) {
  for (int k = 0; k < 9; ++k) matrix[k] = table ? table->table.view().header().rgb_to_target[k] : 0;
}

}  // extern "C"
#endif
