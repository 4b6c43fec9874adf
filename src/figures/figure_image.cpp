#include "figures/figure_image.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <system_error>

#include "imagefile/image_file_output.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize::figures {

namespace {

using OIIO::ImageBufAlgo::TextAlignX;

void draw_text(OIIO::ImageBuf& buf, int x, int y, const std::string& text, int size,
               const std::string& font, float grey, TextAlignX align = TextAlignX::Left) {
  if (font.empty() || text.empty()) return;
  const float colour[3] = {grey, grey, grey};
  OIIO::ImageBufAlgo::render_text(buf, x, y, text, size, font, colour, align);
}

// Writes an 8-bit PNG through imagefile/safe_output.h, so a failed run never leaves a half-written
// figure.
void write_png(OIIO::ImageBuf& buf, const std::string& path) {
  write_image_file(buf, path, OIIO::TypeDesc::UINT8);
}

// A dark-to-bright ramp (black, violet, red, orange, pale yellow) in display sRGB; t in [0, 1].
std::array<float, 3> ramp(double t) {
  static constexpr std::array<std::array<float, 3>, 5> stops{{{0.00f, 0.00f, 0.02f},
                                                              {0.28f, 0.05f, 0.45f},
                                                              {0.70f, 0.16f, 0.35f},
                                                              {0.97f, 0.50f, 0.10f},
                                                              {0.99f, 0.99f, 0.70f}}};
  t = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), stops.size() - 2);
  const float f = static_cast<float>(t - static_cast<double>(i));
  std::array<float, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = (1 - f) * stops[i][k] + f * stops[i + 1][k];
  return c;
}

}  // namespace

namespace {

// The matrix of a transform that should be linear, by converting the unit vectors.
Mat3 matrix_of(const ColourTransform& transform, std::string_view space) {
  Mat3 m{};
  const Xyz columns[3] = {transform(1, 0, 0), transform(0, 1, 0), transform(0, 0, 1)};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[r][c] = columns[c][r];
  // A linear space maps any colour by the matrix; a curve (sRGB - Texture) does not.
  const Xyz probe = transform(0.25, 2.0, 0.5);
  const Xyz want = mul(m, Rgb{0.25, 2.0, 0.5});
  if (relative_error(probe, want) > 1e-5)
    throw Error("colour space '" + std::string(space) +
                "' is not linear: the figures need a scene-linear working space");
  return m;
}

}  // namespace

Mat3 rgb_to_xyz_matrix(const ColourSpaces& spaces, std::string_view space) {
  return matrix_of(spaces.to_xyz(space), space);
}

Mat3 xyz_to_rgb_matrix(const ColourSpaces& spaces, std::string_view space) {
  return matrix_of(spaces.from_xyz(space), space);
}

namespace {

// Display sRGB of XYZ pixels (3 floats each, converted in place), clipped, in a float buffer.
OIIO::ImageBuf display_buffer(int width, int height, std::vector<float>& pixels,
                              const ColourSpaces& spaces) {
  spaces.from_xyz("sRGB - Texture").apply(pixels.data(), pixels.size() / 3);
  for (float& p : pixels) p = std::isfinite(p) ? std::clamp(p, 0.0f, 1.0f) : 0.0f;
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, pixels.data());
  return buf;
}

}  // namespace

void write_sphere_png(const std::string& path, const SphereGeometry& g, const std::vector<Xyz>& xyz,
                      const SphereView& view, const ColourSpaces& spaces) {
  const int size = g.size;
  std::vector<float> pixels(static_cast<std::size_t>(size) * size * 3);
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    // The sphere's pixel already carries its coverage; the background fills the rest.
    const Xyz v = view.exposure * xyz[i] + (1 - g.coverage[i]) * view.background;
    pixels[3 * i] = static_cast<float>(v.X);
    pixels[3 * i + 1] = static_cast<float>(v.Y);
    pixels[3 * i + 2] = static_cast<float>(v.Z);
  }
  OIIO::ImageBuf buf = display_buffer(size, size, pixels, spaces);
  const std::string font = find_font();
  const int text = std::max(10, size / 28);
  draw_text(buf, size / 4, text + 6, view.left_label, text, font, 0.8f, TextAlignX::Center);
  draw_text(buf, 3 * size / 4, text + 6, view.right_label, text, font, 0.8f, TextAlignX::Center);
  write_png(buf, path);
}

void write_xyz_png(const std::string& path, int width, int height, const std::vector<Xyz>& xyz,
                   double exposure, const ColourSpaces& spaces, const std::string& label) {
  if (xyz.size() != static_cast<std::size_t>(width) * height)
    throw Error("'" + path + "': " + std::to_string(xyz.size()) + " pixels for a " +
                std::to_string(width) + " x " + std::to_string(height) + " image");
  std::vector<float> pixels(xyz.size() * 3);
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    const Xyz v = exposure * xyz[i];
    pixels[3 * i] = static_cast<float>(v.X);
    pixels[3 * i + 1] = static_cast<float>(v.Y);
    pixels[3 * i + 2] = static_cast<float>(v.Z);
  }
  OIIO::ImageBuf buf = display_buffer(width, height, pixels, spaces);
  const int text = std::max(10, std::min(width, height) / 16);
  draw_text(buf, 4, text + 2, label, text, find_font(), 0.9f);
  write_png(buf, path);
}

void write_delta_e_png(const std::string& path, const SphereGeometry& g, const MirrorDifference& d,
                       double scale, const std::string& caption) {
  std::vector<bool> covered(g.coverage.size());
  for (std::size_t i = 0; i < covered.size(); ++i) covered[i] = g.coverage[i] != 0;
  write_delta_e_map_png(path, g.size, d.delta_e, covered, scale, caption);
}

void write_delta_e_map_png(const std::string& path, int size, const std::vector<double>& delta_e,
                           const std::vector<bool>& covered, double scale,
                           const std::string& caption) {
  const std::size_t pixels = static_cast<std::size_t>(size) * size;
  if (delta_e.size() != pixels || covered.size() != pixels)
    throw Error("'" + path + "': the difference map is not " + std::to_string(size) + " x " +
                std::to_string(size));
  const int height = delta_e_map_height(size);
  OIIO::ImageSpec spec(size, height, 3, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buf(spec);
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  OIIO::ImageBufAlgo::fill(buf, grey);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * size + x;
      if (!covered[i]) continue;
      const auto c = ramp(delta_e[i] / scale);
      buf.setpixel(x, y, c.data(), 3);
    }
  // The colour bar under the map, with its ends and middle labelled.
  const int bar_top = size + 8, bar_height = 16, margin = size / 16;
  for (int x = margin; x < size - margin; ++x) {
    const auto c = ramp(static_cast<double>(x - margin) / (size - 2 * margin - 1));
    for (int y = bar_top; y < bar_top + bar_height; ++y) buf.setpixel(x, y, c.data(), 3);
  }
  const std::string font = find_font();
  const int text = std::max(10, size / 40);
  const int label_y = bar_top + bar_height + text + 2;
  draw_text(buf, margin, label_y, "0", text, font, 0.0f, TextAlignX::Center);
  draw_text(buf, size / 2, label_y, fmt::format("{:g}", scale / 2), text, font, 0.0f,
            TextAlignX::Center);
  draw_text(buf, size - margin, label_y, fmt::format(">= {:g}", scale), text, font, 0.0f,
            TextAlignX::Center);
  draw_text(buf, size / 2, label_y + text + 8, caption, text, font, 0.0f, TextAlignX::Center);
  write_png(buf, path);
}

}  // namespace spectralize::figures
