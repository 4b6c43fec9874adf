/* The .spztab file format, version 4 (docs/DESIGN.md §14): what `spectralize table` writes and
 * <spectralize/rt.h> reads. Plain C, fixed-width fields, little-endian.
 *
 * A file is a 1024-byte header followed by 17 sections. Every section starts at a multiple of
 * 64 bytes (so a file mapped into memory is aligned for SIMD loads) and holds `count` elements
 * of its type (the header's `sections` table gives offset and count). The checksum is the
 * 64-bit FNV-1a hash (offset basis 14695981039346656037, prime 1099511628211) of the whole
 * file with the checksum field taken as zero. Version 3 adds what a reader needs to check a
 * table's meaning, not only its structure: each band's weights (the target XYZ of a unit
 * sample, so every stored spectrum's colour is checked against its position), the largest
 * sample, and the most simplices of a boundary cell (the bound of a fetch's cost). Version 4's
 * axis lookup names, per bin, the node inside it too, so that a lookup takes one step instead
 * of three. Older versions are refused by version: make the table again with `spectralize
 * table`.
 *
 * Geometry. Reflectance tables live in the colour space's linear RGB (coordinates = RGB);
 * emission tables in CIE xy of the colour's XYZ (scale = X+Y+Z). A grid of nodes (positions
 * per axis) makes cells; a cell is inside the gamut (its 2^d corners' spectra blended over
 * Kuhn simplices: sort the fractional coordinates), outside (colours there are gamut mapped
 * first), or on its boundary (the cell clipped to the gamut, cut into simplices whose vertices
 * are the cell's corners or boundary vertices with exact spectra in closed form: 0/1 per sample
 * except two samples `i`, `j` with values `a`, `b`).
 */
#ifndef SPECTRALIZE_RT_FORMAT_H
#define SPECTRALIZE_RT_FORMAT_H

#include <stdint.h>

#define SPZ_FORMAT_VERSION 4u
#define SPZ_BYTE_ORDER_MARK 0x01020304u /* reads 04 03 02 01 in a little-endian file */
#define SPZ_SECTION_ALIGNMENT 64u
#define SPZ_HEADER_SIZE 1024u
#define SPZ_OUTSIDE 0xFFFFFFFFu      /* a cell outside the gamut; a node without spectrum */
#define SPZ_BOUNDARY_BIT 0x80000000u /* a boundary cell (cells), a boundary vertex (refs) */
/* Bounds a reader enforces, so that loading costs O(file size) and a fetch a bounded time: */
#define SPZ_MAX_CELL_SIMPLICES 65536u /* simplices of one boundary cell */
#define SPZ_MAX_GAMUT_PLANES 1048576u /* planes of the locus, and of the solid */
#define SPZ_MAX_BANDS 65535u          /* samples per spectrum */
/* A fetch is SPZ_EXACT when its spectrum reproduces the colour to this relative error in the
 * table's coordinates (in float: ~1e-7 inside cells, at most this on their boundaries). */
#define SPZ_EXACT_TOLERANCE 1e-5

enum spz_file_mode { SPZ_MODE_EMISSION = 0, SPZ_MODE_REFLECTANCE = 1 };

/* The sections, in file order. Element types and counts: */
enum spz_section {
  SPZ_SECTION_AXIS_X = 0,              /* float[nodes[0]]: node positions, strictly increasing */
  SPZ_SECTION_AXIS_Y = 1,              /* float[nodes[1]] */
  SPZ_SECTION_AXIS_Z = 2,              /* float[nodes[2]] (emission: one position) */
  SPZ_SECTION_AXIS_INVERSE = 3,        /* float[sum of nodes[a]-1]: 1 / interval length, by axis */
  SPZ_SECTION_AXIS_LUT = 4,            /* spz_axis_bin[sum of lut_size[a]], by axis, then one of
                                          zeros (a lookup reads the bin after its own) */
  SPZ_SECTION_CELLS = 5,               /* uint32 per node, x fastest: the cell whose lowest corner
                                          it is, 0 inside, SPZ_OUTSIDE, or SPZ_BOUNDARY_BIT | boundary
                                          cell index (SPZ_OUTSIDE at an axis' last node: no cell) */
  SPZ_SECTION_NODE_SLOTS = 6,          /* uint32 per node, x fastest: the offset of its spectrum in
                                          SPECTRA (slot * bands) or SPZ_OUTSIDE */
  SPZ_SECTION_SPECTRA = 7,             /* float[slots * bands]: node spectra, slot-major */
  SPZ_SECTION_BOUNDARY_CELLS = 8,      /* uint32[2 per boundary cell]: first simplex, count */
  SPZ_SECTION_SIMPLICES = 9,           /* uint32[4 per simplex]: a corner of the cell (bit 0 x,
                                          bit 1 y, bit 2 z upper) or SPZ_BOUNDARY_BIT | boundary
                                          vertex; triangles repeat their first vertex */
  SPZ_SECTION_BOUNDARY_POSITIONS = 10, /* double[3 per boundary vertex]: table coordinates */
  SPZ_SECTION_BOUNDARY_MASKS = 11,     /* uint32[mask_words per boundary vertex]: samples at 1 */
  SPZ_SECTION_BOUNDARY_PICKS = 12,     /* uint32 per boundary vertex: i | j << 16 */
  SPZ_SECTION_BOUNDARY_VALUES = 13,    /* float[2 per boundary vertex]: the values at i and j */
  SPZ_SECTION_LOCUS_PLANES = 14,       /* double[4 per plane]: n, d of the spectral locus (target
                                          XYZ, n . t <= d inside) */
  SPZ_SECTION_SOLID_PLANES = 15, /* double[4 per plane]: the reflectance solid (reflectance) */
  SPZ_SECTION_BAND_WEIGHTS = 16, /* double[3 per band]: the target X, Y, Z of a unit sample of
                                    band k (every stored spectrum s reproduces sum_k s_k w_k) */
  SPZ_SECTION_COUNT = 17
};

/* One bin of an axis' lookup. A position v falls in bin
 * b = (uint32_t)min(max((v - lut_origin) * lut_inverse_bin, 0), lut_size - 1), in float. `split`
 * is the one interior node (positions 1 to nodes - 2) whose bin is b, or +infinity; below it v
 * lies in the interval k = the number of interior nodes of lower bins, at or above it in k + 1,
 * whose entries are the next bin's (which starts in that interval). `node` is k times the
 * axis' node stride (1, nodes[0], nodes[0] * nodes[1]): the offsets of the three axes add up
 * to the index of the cell's lowest node, in CELLS and NODE_SLOTS alike. `position` and
 * `inverse` are the interval's start and 1 / length (the axis' and the inverse section's
 * values; 0 for an axis of one node). Bins are no wider than half the shortest interval, so no
 * bin holds two nodes: a lookup reads its bin and the next at once and has the cell and the
 * fraction without a further step. */
typedef struct spz_axis_bin {
  uint32_t node;
  float split;
  float position;
  float inverse;
} spz_axis_bin;

typedef struct spz_section_entry {
  uint64_t offset; /* bytes from the start of the file, a multiple of 64 */
  uint64_t count;  /* elements of the section's type */
} spz_section_entry;

typedef struct spz_file_header {
  char magic[8];            /*    0 "SPZTABLE" */
  uint32_t version;         /*    8 SPZ_FORMAT_VERSION */
  uint32_t byte_order;      /*   12 SPZ_BYTE_ORDER_MARK */
  uint64_t file_size;       /*   16 bytes */
  uint64_t checksum;        /*   24 FNV-1a 64 of the file with this field zero */
  uint32_t header_size;     /*   32 SPZ_HEADER_SIZE */
  uint32_t mode;            /*   36 spz_file_mode */
  uint32_t bands;           /*   40 samples per spectrum, N */
  uint32_t mask_words;      /*   44 (N + 31) / 32 */
  double lambda_start;      /*   48 nm of sample 0 */
  double lambda_step;       /*   56 nm between samples */
  double rgb_to_xyz[9];     /*   64 the colour space's RGB -> CIE XYZ (D65), row-major */
  double rgb_to_target[9];  /*  136 RGB -> the XYZ the spectra reproduce (white balanced) */
  double target_to_rgb[9];  /*  208 its inverse */
  double locus_white[3];    /*  280 gamut mapping: toward this white (x Y) outside the locus */
  double solid_white[3];    /*  304 reflectance: the white of rho == 1 (Y = 1) */
  double locus_margin;      /*  328 mapped colours stop this fraction short of the locus */
  double solid_margin;      /*  336 ... of the solid */
  double snap_tolerance;    /*  344 a mapping move below this (relative) is rounding */
  double locus_scale;       /*  352 the gamuts' magnitudes (containment is tested to 1e-12 of */
  double solid_scale;       /*  360 |colour|, docs/DESIGN.md §5) */
  uint32_t nodes[3];        /*  368 nodes per axis (emission: nodes[2] == 1) */
  uint32_t lut_size[3];     /*  380 bins of each axis' interval lookup */
  float lut_origin[3];      /*  392 position of bin 0 */
  float lut_inverse_bin[3]; /*  404 bins per unit */
  uint32_t section_count;   /*  416 SPZ_SECTION_COUNT */
  uint32_t resolution[3];   /*  420 builder's node spacing: steps, coarse steps, chroma steps */
  spz_section_entry sections[SPZ_SECTION_COUNT]; /* 432 */
  double sample_bound;         /*  704 no stored sample exceeds it (reflectance: <= 1; emission:
                                       at most what a spectrum of X+Y+Z = 1 can hold) */
  uint32_t max_cell_simplices; /*  712 the most simplices of a boundary cell (a fetch's cost) */
  uint32_t reserved;           /*  716 0 */
  char colorspace[104];        /*  720 the OCIO colour space's name, NUL-terminated */
  char interop_id[32];         /*  824 its colour interop ID, or "" */
  char model[32];              /*  856 the spectrum model of the node spectra */
  char observer[16];           /*  888 cie1931 | cie1964 */
  char illuminant[32];         /*  904 reference illuminant (reflectance) */
  char emission_basis[32];     /*  936 flat or an illuminant (emission) */
  char generator[56];          /*  968 "spectralize <version>" */
} spz_file_header;             /* 1024 bytes */

#endif /* SPECTRALIZE_RT_FORMAT_H */
