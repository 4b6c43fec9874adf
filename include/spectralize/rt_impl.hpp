// spectralize::rt -- the definitions behind <spectralize/rt.hpp> that are not on the hot path:
// the loader and validator of table files (docs/DESIGN.md §14), the rare paths of a fetch
// (boundary cells, colours mapped into the gamut: docs/DESIGN.md §5), fetch_array, and the C API
// of <spectralize/rt.h>. rt.hpp and rt.h include this file in the one translation unit that
// defines SPECTRALIZE_RT_IMPLEMENTATION (src/rt_c/rt_c.cpp for libspectralize_rt), which
// compiles them. Included without it, it gives only closest_in_simplex, whose arithmetic the
// table writer (src/core/tables/exact_table.cpp) shares with the boundary cells here.
#ifndef SPECTRALIZE_RT_IMPL_HPP
#define SPECTRALIZE_RT_IMPL_HPP

namespace spz {
namespace detail {

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

}  // namespace detail
}  // namespace spz

#endif  // SPECTRALIZE_RT_IMPL_HPP

// The definitions: once per translation unit, where SPECTRALIZE_RT_IMPLEMENTATION is defined
// (outside the include guard: this file may have been included before without it).
#if defined(SPECTRALIZE_RT_IMPLEMENTATION) && !defined(SPECTRALIZE_RT_DEFINED)
#define SPECTRALIZE_RT_DEFINED

#include <spectralize/rt.hpp>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <new>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/stat.h>
#endif

namespace spz {

namespace detail {

inline void say(char* error, std::size_t size, const char* format, ...) noexcept {
  if (!error || size == 0) return;
  va_list args;
  va_start(args, format);
  std::vsnprintf(error, size, format, args);
  va_end(args);
}

inline bool finite(double v) noexcept {
  return std::isfinite(v);
}

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

bool Gamut::contains(const Vec3& t) const noexcept {
  const double tol = 1e-12 * max_abs(t);  // relative: near black the gamuts are cones
  for (std::uint64_t f = 0; f < count; ++f)
    if (dot(planes + 4 * f, t) > planes[4 * f + 3] + tol) return false;
  return true;
}

double Gamut::max_step(const Vec3& from, const Vec3& to) const noexcept {
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

bool TableView::open(const void* data, std::size_t size, char* error,
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
bool TableView::check_meaning(char* error, std::size_t error_size) const noexcept {
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

bool TableView::locate(const double u[3], int i[3], double f[3], bool clamp,
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
bool TableView::close_to(const double u[3], const double v[3]) const noexcept {
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

SPZ_COLD bool TableView::boundary_of_node(std::uint32_t code, std::uint32_t node, const double u[3],
                                          Spectrum& s) const noexcept {
  const int i[3] = {static_cast<int>(node % n_[0]), static_cast<int>((node / n_[0]) % n_[1]),
                    static_cast<int>(node / stride_[2])};
  return boundary_blend(code & ~SPZ_BOUNDARY_BIT, i, u, s, false, nullptr);
}

SPZ_COLD bool TableView::boundary_blend(std::uint32_t b, const int i[3], const double u[3],
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

bool TableView::cell_blend(const int i[3], const double f[3], const double u[3], Spectrum& s,
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

#if defined(__SSE2__)
bool TableView::squared_axes(std::uint32_t& zero_node, float& steps) const noexcept {
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
#endif

bool TableView::blend(const double u[3], Spectrum& s, bool nearest,
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

int TableView::map_target(detail::Vec3& t) const noexcept {
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

SPZ_COLD int TableView::slow_fetch(const float rgb[3], Spectrum& s) const noexcept {
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

int TableView::map_into_gamut(const double rgb[3], double mapped[3]) const noexcept {
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

std::size_t fetch_array(const TableView& t, const float* rgb, std::size_t n, const float* lambda_nm,
                        std::size_t m, float* out, int* statuses, std::size_t counts[4]) noexcept {
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

// --- Table ---

bool Table::load(const char* path, char* error, std::size_t error_size) noexcept {
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

// The C API of <spectralize/rt.h>.
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

#endif  // SPECTRALIZE_RT_IMPLEMENTATION
