#pragma once
// The paper's test scene: a Lambertian sphere seen by an orthographic camera and lit by a
// point light at the eye, so each point reflects in proportion to n.v. Rendered twice, by an
// RGB renderer (albedo times light colour, per channel) and by a spectral renderer (reflectance
// times light per wavelength band, integrated with the CIE observer), and compared half against
// half. No OIIO/OCIO here: callers convert and write (figure_image.h).

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "spectralize/core/xyz.h"

namespace spectralize::figures {

/// A linear RGB triple in a working space (e.g. Linear Rec.709).
struct Rgb {
  double r = 0, g = 0, b = 0;
};

/// A 3x3 matrix (row-major), e.g. a linear RGB space's RGB -> XYZ.
using Mat3 = std::array<std::array<double, 3>, 3>;

/// m * (r, g, b). Cost: O(1).
Xyz mul(const Mat3& m, const Rgb& rgb);
/// xyz_to_rgb * (X, Y, Z). Cost: O(1).
Rgb to_rgb(const Mat3& xyz_to_rgb, const Xyz& xyz);

/// Per pixel of a size x size image of the unit sphere filling the frame: the mean of
/// max(0, n.v) over supersample^2 subsamples (0 off the sphere) and the covered fraction.
struct SphereGeometry {
  int size = 0;
  std::vector<double> shading;
  std::vector<double> coverage;

  /// Orthographic view along -z; n.v = sqrt(1 - x^2 - y^2) at image point (x, y) in [-1, 1]^2.
  /// Pixels x and size-1-x get bit-identical values (the halves are compared pixel by pixel).
  /// Throws Error for size < 2 or supersample < 1. Cost: O(size^2 supersample^2).
  static SphereGeometry orthographic(int size, int supersample);
};

/// The RGB renderer: XYZ of albedo (x) light (per channel) * shading, per pixel; 0 off the
/// sphere. `rgb_to_xyz` is the working space's matrix. Cost: O(size^2).
std::vector<Xyz> render_rgb(const SphereGeometry& geometry, const Rgb& albedo, const Rgb& light,
                            const Mat3& rgb_to_xyz);

/// The spectral renderer: per pixel the radiance of each band, rho_i * shading, integrated with
/// `band_weights` (the light folded into the observer's weights: W_i = sum_k tau cmf E h_i,
/// SampleWeights under the light), then scaled per component by `calibration` (the fixed
/// diagonal that maps the renderer's white to the working space's, same for every light).
/// Throws Error if the spans differ in length. Cost: O(size^2 N).
std::vector<Xyz> render_spectral(const SphereGeometry& geometry,
                                 std::span<const double> reflectance,
                                 std::span<const Xyz> band_weights, const Xyz& calibration);

/// Left half (x < size/2) from `left`, right half from `right`. Cost: O(size^2).
std::vector<Xyz> split_halves(int size, const std::vector<Xyz>& left,
                              const std::vector<Xyz>& right);

/// CIEDE2000 between mirror pixels of a split image: (x, y) of the left half against
/// (size-1-x, y) of the right half, on the sphere only.
struct MirrorDifference {
  std::vector<double> delta_e;  // per pixel (both pixels of a pair get its value); 0 off sphere
  double max = 0;
  double mean = 0;
  std::size_t pairs = 0;  // pixel pairs compared
};

/// Compares the halves of `split` with CIELAB relative to `white`. Cost: O(size^2).
MirrorDifference mirror_delta_e(const SphereGeometry& geometry, const std::vector<Xyz>& split,
                                const Xyz& white);

}  // namespace spectralize::figures
