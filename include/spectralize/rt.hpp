// spectralize::rt -- the C++ API (C++17, no dependencies) of the render-time evaluator of exact
// spectra; see <spectralize/rt.h> for the C API over it and docs/DESIGN.md §14 for the table and
// why it is exact.
//
//   spz::Table table;
//   std::string error;
//   if (!table.load("srgb.spztab", &error)) ...;        // never throws; checks what it means
//   spz::Spectrum s;
//   const int status = table.view().fetch(rgb, s);       // SPZ_EXACT, SPZ_MAPPED, < 0 invalid
//   float v[4];
//   spz::eval4(s, lambdas, v);                           // or spz::eval(s, 550.f)
//
// Header-only, in two files: this one is the API (declarations, and the hot paths inline:
// fetch, eval, eval4, samples); <spectralize/rt_impl.hpp> holds the loader, the validator, the
// rare paths (boundary cells, colours mapped into the gamut) and the C API's definitions. Define
// SPECTRALIZE_RT_IMPLEMENTATION in exactly one C++ translation unit of the program before
// including this header (or rt.h) there: that unit compiles them. Every other unit includes
// this header alone.
//
//   #define SPECTRALIZE_RT_IMPLEMENTATION   // one .cpp file of the program
//   #include <spectralize/rt.hpp>
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
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// The rare paths (boundary cells, colours mapped into the gamut) out of line and out of the
// hot code (declared so, the calls to them are laid out as unlikely); eval4 into the caller's
// loop.
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
// The writer (src/core/tables/table_file.cpp) computes it with this function too.
inline std::uint64_t table_checksum(const unsigned char* data, std::size_t size) noexcept {
  const unsigned char zeros[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::uint64_t h = kFnv1aOffsetBasis;
  h = fnv1a(data, 24, h);
  h = fnv1a(zeros, 8, h);
  return fnv1a(data + 32, size - 32, h);
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

// A colour in double precision: target XYZ, or table coordinates.
struct Vec3 {
  double x, y, z;
};

// A half-space gamut in target XYZ, as the spectralize CLI tests it (docs/DESIGN.md §5).
struct Gamut {
  const double* planes = nullptr;  // n.x, n.y, n.z, d per plane
  std::uint64_t count = 0;
  // Whether t is inside every plane (to 1e-12 relative). Cost: O(planes).
  bool contains(const Vec3& t) const noexcept;
  // The largest step in [0, 1] from `from` toward `to` that stays inside. Cost: O(planes).
  double max_step(const Vec3& from, const Vec3& to) const noexcept;
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
  // The lookups: the fast ones (fast_blend, fast_blend_sse, fast_reflectance) inline below, the
  // others, the loader's checks and the mapping in rt_impl.hpp.
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
  SPZ_COLD bool boundary_of_node(std::uint32_t code, std::uint32_t node, const double u[3],
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
  SPZ_COLD int slow_fetch(const float rgb[3], Spectrum& s) const noexcept;
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

// The sample interval of a wavelength and the position in it. The fraction is taken from the
// interval's own start (exact in float for grids of whole nanometres), not from the position
// on the whole grid, whose float rounding would be ~1e-5 of a sample apart at 780 nm.
inline void interval_of(const TableView& t, float lambda_nm, std::uint32_t& k, float& f) noexcept {
  const float x = (lambda_nm - t.start_) * t.inv_step_;
  k = std::min(static_cast<std::uint32_t>(x), t.bands_ - 2);
  f = (lambda_nm - (t.start_ + static_cast<float>(k) * t.step_)) * t.inv_step_;
  f = std::min(std::max(f, 0.0f), 1.0f);
}

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

/// The spectrum's value at `lambda_nm`: the piecewise-linear function through its samples, 0
/// outside the table's wavelengths. Cost: O(1), 8 loads.
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
std::size_t fetch_array(const TableView& t, const float* rgb, std::size_t n, const float* lambda_nm,
                        std::size_t m, float* out, int* statuses, std::size_t counts[4]) noexcept;

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

inline const TableView& TableView::none() noexcept {
  static constexpr TableView empty{};  // constant-initialised: no guard, no runtime library
  return empty;
}

}  // namespace spz

/// A loaded table of the C API.
struct spz_table {
  spz::Table table;
};

// rt.hpp has been read whole (rt.h may now include it again for the definitions below).
#define SPECTRALIZE_RT_HPP_DONE
#endif  // SPECTRALIZE_RT_HPP

// The definitions (rt_impl.hpp), in the one translation unit that defines
// SPECTRALIZE_RT_IMPLEMENTATION (outside the include guard: rt.hpp may have been included
// before without it).
#if defined(SPECTRALIZE_RT_IMPLEMENTATION) && !defined(SPECTRALIZE_RT_DEFINED)
#include <spectralize/rt_impl.hpp>
#endif
