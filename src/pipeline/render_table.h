#pragma once
// The render-time table of a colour space (docs/DESIGN.md §14): `spectralize table` and
// spectralize.table() build an ExactTable for the settings in the RGB of a linear OCIO colour
// space (its RGB -> XYZ matrix measured through OCIO) and write it as a .spztab file, which
// renderers read with <spectralize/rt.h>.

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "colour/colour_space.h"
#include "core/colorimetry/mat3.h"
#include "core/tables/exact_table.h"
#include "core/tables/spectral_table.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"
#include "settings/settings.h"

namespace spectralize {

/// The frame of a job's exact table (core/tables/spectral_table.h): the space's matrix
/// (ColourSpaceFacts::rgb_to_xyz, the unit colours' XYZ, so encoded spaces have one too) when
/// its white is D65 (so that RGB (1, 1, 1) is the perfect reflector and the table's dense
/// cells cover the space's cube, as in a render-time table for it), else Linear Rec.709's.
/// Cost: the space's facts (an OCIO processor the first time).
Mat3 table_frame(const ColourSpaces& spaces, std::string_view space);

/// A renderer's matrix (`--rgb-to-xyz`, core/renderer_frame.h) resolved under the settings'
/// observer. Throws Error for an unknown illuminant. Cost: O(reference table).
Mat3 renderer_matrix(const Settings& settings);

/// A renderer's XYZ in the table's units: 1 for lights; for reflectances the illuminant's Y
/// over 360-830 nm (a renderer's normalisation) over that of rho == 1 on the grid (the
/// table's, docs/DESIGN.md §3): 1 on a 360:830 grid. Cost: O(reference table).
double renderer_units(const Spectralizer& sp);

/// The CIE xy chromaticity of column `c` of an RGB -> XYZ matrix: that primary's. Cost: O(1).
std::array<double, 2> chromaticity_of_column(const Mat3& m, int c);

/// The largest difference of a primary's x or y between a renderer's matrix and the space
/// the table is named after: 1e-3 holds every published rounding of a space's primaries.
inline constexpr double kPrimariesTolerance = 1e-3;

/// How far a renderer's matrix (its columns the primaries, its row sums the white) is from
/// being for `space`: the largest difference of a primary's x or y, the smaller of two
/// comparisons on the space's own terms (docs/DESIGN.md §14): with the primaries its standard
/// states (ACES2065-1: AP0; ACEScg: AP1), the white free (a renderer's comes from its own
/// illuminant data); and both adapted to D65 by Bradford from their own whites, as configs
/// adapt (a space no standard names, DCI-P3 with the DCI white). INFINITY for a space without
/// primaries. Cost: O(1).
double renderer_primaries_difference(const ColourSpaceFacts& space, const Mat3& renderer);

/// Table settings: an output named .spztab, the config loads, the colour space (default: the
/// config's scene_linear role) exists and is linear RGB (an encoded or log space is refused,
/// naming the linear space with its primaries when the config has one: renderers decode and
/// filter textures in linear before the lookup), mode auto is reflectance (plan_colours of a
/// table). Throws Error naming the option. Cost: the config's parse, OCIO processors.
JobPlan plan_table(Settings settings, const std::string& output, const OptionNames& names);

/// The share of the RGB unit cube whose colours `table` reproduces exactly: of the steps^3
/// cell centres of [0, 1]^3, those whose target (the table's own) lies in the mode's gamut
/// (the reflectance solid; for emission the spectral locus) as the mapping decides it
/// (docs/DESIGN.md §5; within the snap tolerance is inside). The rest are mapped. Thread-safe.
/// Cost: steps^3 gamut tests, O(facets) each (~0.2 s at 32 on one core).
double feasible_share(const Spectralizer& sp, const ExactTable& table, int steps = 32);

/// A built table file.
struct RenderTable {
  std::string bytes;       // the .spztab file
  std::string colorspace;  // the space it is for
  ExactTableStats stats;
  std::size_t spectra = 0;         // node spectra stored
  std::size_t boundary_cells = 0;  // cells clipped to the gamut
  double feasible = 0;             // feasible_share() of the table's space
  double seconds = 0;              // to build it
};

/// Builds the table `plan` (plan_table) says, on `settings.threads` cores (0: all). The bytes
/// depend only on the settings. Cost: every node's solve (~40 us each at 5 nm; ~20 000 nodes
/// per reflectance table), a few seconds.
RenderTable make_render_table(const JobPlan& plan, const LogFn& log);

}  // namespace spectralize
