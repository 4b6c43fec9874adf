#pragma once
// Writing the figures' images: sphere renders (CIE XYZ) through the shipped OCIO config's sRGB
// display encoding to 8-bit PNG, and colour-difference maps with a colour bar. OIIO and OCIO
// stay in figure_image.cpp.

#include <string>
#include <string_view>
#include <vector>

#include "colour/colour_space.h"
#include "figures/sphere_render.h"

namespace spectralize::figures {

/// The RGB -> XYZ (D65) matrix of a linear colour space of the config, read off OCIO by
/// converting the unit vectors; throws Error if the space is not linear. Cost: ~ms (OCIO).
Mat3 rgb_to_xyz_matrix(const ColourSpaces& spaces, std::string_view space);
/// The XYZ (D65) -> RGB matrix of the same space, read off OCIO's inverse transform the same
/// way. Cost: ~ms (OCIO).
Mat3 xyz_to_rgb_matrix(const ColourSpaces& spaces, std::string_view space);

/// How a sphere image is shown: exposure (same for both halves), background and labels.
struct SphereView {
  double exposure = 1;                     // linear scale applied before display encoding
  Xyz background{0.0190, 0.0200, 0.0218};  // a dark neutral grey, XYZ (D65 white, Y = 0.02)
  std::string left_label = "RGB";          // drawn at the top of each half
  std::string right_label = "spectral";
};

/// Writes `xyz` (size x size, 0 off the sphere), blended over the background by coverage, as
/// display sRGB (OCIO 'sRGB - Texture', clipped) 8-bit PNG; written to a temporary file and
/// renamed. Labels are skipped if no DejaVu Sans font is installed. Throws Error naming `path`
/// and the reason. Cost: O(size^2) + PNG encode, ~20 ms at 512^2.
void write_sphere_png(const std::string& path, const SphereGeometry& geometry,
                      const std::vector<Xyz>& xyz, const SphereView& view,
                      const ColourSpaces& spaces);

/// Writes a width x height XYZ image (row-major from the top) times `exposure` as display sRGB
/// (OCIO 'sRGB - Texture', clipped) 8-bit PNG with `label` at the top left (skipped without a
/// font), through a temporary file. Throws Error naming `path`. Cost: O(pixels) + PNG encode.
void write_xyz_png(const std::string& path, int width, int height, const std::vector<Xyz>& xyz,
                   double exposure, const ColourSpaces& spaces, const std::string& label = "");

/// Writes a per-pixel CIEDE2000 map (size x size, row-major; pixels whose `covered` is false
/// grey) as a heat map with a colour bar and `caption` below, as write_delta_e_png. Throws Error
/// naming `path`. Cost: O(size^2).
void write_delta_e_map_png(const std::string& path, int size, const std::vector<double>& delta_e,
                           const std::vector<bool>& covered, double scale,
                           const std::string& caption);

/// Writes the per-pixel CIEDE2000 of a mirror comparison as a heat map (0 black .. `scale`
/// white-yellow, off-sphere grey) with a colour bar and `caption` below: size x (size + 80)
/// pixels, 8-bit PNG via a temporary file. Throws Error naming `path`. Cost: O(size^2).
void write_delta_e_png(const std::string& path, const SphereGeometry& geometry,
                       const MirrorDifference& difference, double scale,
                       const std::string& caption);

/// Height in pixels of a difference map for a sphere image of `size`. Cost: O(1).
inline constexpr int delta_e_map_height(int size) {
  return size + 80;
}

}  // namespace spectralize::figures
