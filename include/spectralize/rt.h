/* spectralize::rt -- exact spectra at render time, from a table made by `spectralize table`.
 *
 * The C API. spz_fetch turns a linear RGB colour of the table's colour space into a small
 * value (spz_spectrum) whose spectrum reproduces the colour exactly (relative XYZ <= 1e-5 in
 * float under the table's conventions), stays in [0, 1] for reflectances and >= 0 for lights,
 * and needs no solver: the blend of up to four precomputed exact spectra. spz_eval gives its
 * value at any wavelength (the piecewise-linear spectrum through the table's samples, 0 outside
 * their range). No allocation, no exceptions, no virtual calls in fetch and eval; a loaded table
 * is read-only and may be shared by any number of threads.
 *
 * For any file and any colour: loading costs O(file size) and checks the table's structure and
 * meaning (every stored spectrum reproduces the colour of its position; bounds; matrices
 * inverse to each other; the gamut holding the table's own colours); a fetch costs O(1) inside
 * the grid's cells, at most O(max_cell_simplices) (a header field, <= SPZ_MAX_CELL_SIMPLICES)
 * on the gamut's boundary and O(planes) (<= SPZ_MAX_GAMUT_PLANES) to map a colour in; no input
 * is undefined behaviour; a spectrum said SPZ_EXACT or SPZ_MAPPED is finite, >= 0, and <= 1 for
 * a reflectance (bit for bit), and SPZ_EXACT only when it reproduces the colour to
 * SPZ_EXACT_TOLERANCE relative, at any magnitude.
 *
 * Header-only, or compiled into libspectralize_rt (.so/.a). Header-only, define
 * SPECTRALIZE_RT_IMPLEMENTATION in exactly one C++ translation unit and include this header (or
 * <spectralize/rt.hpp>) there, after any earlier inclusion too: that unit then compiles these
 * functions and what rt.hpp's C++ API does not define inline (<spectralize/rt_impl.hpp>: the
 * loader, the validator, the rare paths). Every other C or C++ unit just includes the header.
 *
 *   spz_table *t = spz_table_load("srgb.spztab", err, sizeof err);   (NULL + message)
 *   spz_spectrum s;
 *   int status = spz_fetch(t, rgb, &s);  (0 exact, 1 mapped into the gamut first, < 0 invalid)
 *   float v = spz_eval(&s, 550.0f);
 *   spz_table_free(t);
 */
#ifndef SPECTRALIZE_RT_H
#define SPECTRALIZE_RT_H

#include <stddef.h>
#include <stdint.h>

/* The compiled library (libspectralize_rt) exports these functions and nothing else; built
 * into a program from the header, they keep the program's own visibility. */
#if defined(SPECTRALIZE_RT_EXPORTS) && defined(__GNUC__)
#define SPZ_API __attribute__((visibility("default")))
#else
#define SPZ_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* A loaded table (opaque). */
typedef struct spz_table spz_table;

/* A colour's spectrum: the blend of up to four of the table's spectra. A small value; valid
 * while its table is loaded. A zero-initialised one ({0}) is the zero spectrum of no table:
 * it evaluates to 0 everywhere. */
typedef struct spz_spectrum {
  const void* table;  /* the table's data (internal) */
  uint32_t vertex[4]; /* spectrum slots, or (high bit) boundary spectra of the table */
  float weight[4];    /* barycentric weights, sum 1 */
  float scale;        /* lights: the colour's X+Y+Z (any brightness); 1 for reflectances;
                         0 for the zero spectrum */
  uint32_t flags;     /* internal: bit 0 a boundary spectrum is blended, bit 1 reflectance */
} spz_spectrum;

/* spz_fetch results. */
enum {
  SPZ_EXACT = 0,    /* the colour's own exact spectrum */
  SPZ_MAPPED = 1,   /* outside the gamut: mapped in as the spectralize CLI does, then exact */
  SPZ_INVALID = -1, /* NaN, infinite, a light too bright for a finite float spectrum, or no
                       table: the zero spectrum */
  SPZ_NEGATIVE = -2 /* negative luminance (no light or surface has it): the zero spectrum */
};

/* Loads and validates a table file: its 1024-byte header first (signature, version, size),
 * then every size, offset, index and value, the checksum, and the table's meaning (above).
 * Returns NULL and a message naming the file, the field and the reason in `error` (if not
 * NULL) for anything unusable; a table of an older format version is to be made again with
 * `spectralize table`. Cost: reading the file, O(file size). */
SPZ_API spz_table* spz_table_load(const char* path, char* error, size_t error_size);

/* Frees a table (NULL is allowed). */
SPZ_API void spz_table_free(spz_table* table);

/* The spectrum of a linear RGB colour of the table's colour space (a NULL table gives the zero
 * spectrum and SPZ_INVALID). Cost: O(1): a cell lookup and four weights; cells on the gamut's
 * boundary test their simplices (at most max_cell_simplices); a colour outside the gamut is
 * mapped first (O(planes), a few thousand). */
SPZ_API int spz_fetch(const spz_table* table, const float rgb[3], spz_spectrum* out);

/* The spectrum's value at lambda_nm (0 outside the table's wavelengths). Cost: O(1). */
SPZ_API float spz_eval(const spz_spectrum* s, float lambda_nm);

/* The values at four wavelengths (e.g. a path's hero wavelengths). Cost: O(1). */
SPZ_API void spz_eval4(const spz_spectrum* s, const float lambda_nm[4], float out[4]);

/* spz_fetch then spz_eval4 in one call (a texture lookup that evaluates at once): the same
 * status and values bit for bit; the spectrum also into `keep` unless it is NULL. Cost: as
 * both, a few cycles less (the spectrum stays out of memory on the common path). */
SPZ_API int spz_fetch_eval4(const spz_table* table, const float rgb[3], const float lambda_nm[4],
                            float out[4], spz_spectrum* keep);

/* All samples of the spectrum, spz_table_bands() floats into out. Cost: O(bands). */
SPZ_API void spz_samples(const spz_spectrum* s, float* out);

/* The samples of the spectrum into out, which holds `capacity` floats: returns the spectrum's
 * band count, and writes its samples only when that is <= capacity (a consumer sized for 81
 * bands is not overrun by a 1 nm table). The zero spectrum of no table writes `capacity` zeros
 * and returns 0. Cost: O(bands). */
SPZ_API size_t spz_samples_n(const spz_spectrum* s, float* out, size_t capacity);

/* The spectrum's band count (0 for the zero spectrum of no table). Cost: O(1). */
SPZ_API size_t spz_spectrum_bands(const spz_spectrum* s);

/* A bound of the spectrum's value at every wavelength, as spz_eval and spz_eval4 return them:
 * its largest sample, 8 ulp up for their rounding (pbrt's MaxValue(), light bounds, a medium's
 * majorant), without keeping the table beside it. Cost: O(bands). */
SPZ_API float spz_spectrum_max(const spz_spectrum* s);

/* The spectra of n colours (rgb: 3n floats, linear RGB of the table's space) into out, n rows:
 * at the m wavelengths of lambda_nm, or, when lambda_nm is NULL, at the table's own bands
 * (spz_table_bands() floats a row; m is ignored). statuses (n ints) and counts (exact,
 * mapped, invalid, negative) may be NULL. Returns the row length. Thread-safe: threads may
 * fill disjoint rows of one array (bakers, GPU uploads). Cost: n fetches and n * row
 * evaluations. */
SPZ_API size_t spz_fetch_array(const spz_table* table, const float* rgb, size_t n,
                               const float* lambda_nm, size_t m, float* out, int* statuses,
                               size_t counts[4]);

/* Samples per spectrum, and their wavelengths: start + i * step nm (0 for a NULL table).
 * Cost: O(1). */
SPZ_API size_t spz_table_bands(const spz_table* table);
SPZ_API void spz_table_wavelengths(const spz_table* table, float* start_nm, float* step_nm);

/* 0 emission (lights), 1 reflectance (surfaces), -1 a NULL table. Cost: O(1). */
SPZ_API int spz_table_mode(const spz_table* table);

/* The OCIO colour space the table's RGB belongs to ("" for NULL), and its RGB -> CIE XYZ (D65)
 * matrix (row-major). Cost: O(1). */
SPZ_API const char* spz_table_colorspace(const spz_table* table);
SPZ_API void spz_table_rgb_to_xyz(const spz_table* table, double matrix[9]);

/* RGB -> the XYZ the spectra reproduce exactly (row-major), under the table's observer and
 * illuminant, in the table's units (a reflectance's Y relative to rho == 1 on its grid): the
 * colour space's matrix white balanced to the illuminant, or, for a table made with
 * `spectralize table --rgb-to-xyz` on 360:830, the renderer's own matrix. Cost: O(1). */
SPZ_API void spz_table_rgb_to_target(const spz_table* table, double matrix[9]);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* SPECTRALIZE_RT_H */

/* With SPECTRALIZE_RT_IMPLEMENTATION, rt.hpp includes the definitions (rt_impl.hpp) at its end:
 * outside the include guard, so that the define works in a unit that included this header
 * before. */
#if defined(__cplusplus) && defined(SPECTRALIZE_RT_IMPLEMENTATION) && \
    !defined(SPECTRALIZE_RT_DEFINED) &&                               \
    (!defined(SPECTRALIZE_RT_HPP) || defined(SPECTRALIZE_RT_HPP_DONE))
#include <spectralize/rt.hpp>
#endif
