#pragma once
// The scene's inputs as a renderer sees them: RGB images converted by OCIO to the tables'
// linear space (testimages/ charts and HDRIs), the measured truth behind the ColorChecker chart
// (its 24 reflectances in the chart's layout, testimages/README.md), and lights of one CIE
// illuminant's spectrum whose brightness follows a map.

#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "figures/sphere_render.h"
#include "path_tracer/sampled_spectra.h"
#include "spectralize/core/xyz.h"

namespace spectralize::path_tracer {

/// A width x height image of linear RGB (3 floats per texel, row-major from the top).
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

/// Reads the first three channels of `path` (any format OIIO reads) and converts them with OCIO
/// from `file_space` to `linear_space`. Throws Error naming the file and the reason. Cost:
/// reading the file + O(pixels).
RgbImage read_linear_rgb(const std::string& path, const std::string& file_space,
                         const std::string& linear_space, const ColourSpaces& spaces);

/// The CIE XYZ of each texel of a linear image, by `rgb_to_xyz`. Cost: O(pixels).
std::vector<Xyz> texel_xyz(const RgbImage& image, const figures::Mat3& rgb_to_xyz);

/// The ColorChecker chart of testimages/colorchecker_srgb*.png (110 x 74: 6 x 4 patches of
/// 16 px with a 2 px black gutter, in the column order of data/colorchecker_n_ohta_5nm.csv) as
/// measured reflectances: each patch texel its patch's spectrum (380..780 nm, 5 nm), the gutter
/// 0. Throws Error for another size. Cost: O(texels).
SampledSpectra measured_colorchecker(int width, int height);

/// The patch (0..23, CSV column order) under texel (x, y) of the chart, or -1 in the gutter.
/// Cost: O(1).
int colorchecker_patch(int x, int y);

/// CIE illuminant `name` on the 1 nm reference table scaled to Y = 1 in emission units
/// (docs/DESIGN.md §3: Y = sum tau ybar E / K), as samples at 360..830 nm; its XYZ in `xyz`.
/// Throws Error for an unknown name. Cost: O(471).
std::vector<float> unit_illuminant(const std::string& name, Xyz* xyz);

}  // namespace spectralize::path_tracer
