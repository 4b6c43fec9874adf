#pragma once
// Spectrum plots: a description (curves, title lines, legend swatches) drawn either as a raster
// image with OpenImageIO's ImageBufAlgo render functions or as SVG text. Both come from one
// layout, so they look the same. No OIIO types in this header.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace spectralize {

class ColourSpaces;

/// A colour on the display: components encoded in the plot's display-referred space
/// (PlotSpaces::encoded), clipped to [0, 1] when drawn.
struct PlotColour {
  float r = 0, g = 0, b = 0;
};

/// One spectrum on the plot.
struct PlotCurve {
  std::string label;                 // legend text, e.g. the input colour "0.21,0.72,0.15"
  std::vector<double> wavelengths;   // nm, increasing
  std::vector<double> values;        // one per wavelength
  PlotColour colour;                 // of the line and the sample points
  std::vector<PlotColour> swatches;  // side by side in the legend, one per SpectrumPlot label
};

/// Everything a plot shows. The image is kPlotWidth x kPlotHeight whatever the content.
struct SpectrumPlot {
  std::vector<std::string> title;  // up to 3 lines; the first is drawn larger
  std::string x_label = "wavelength (nm)";
  std::string y_label = "value";
  double y_top_at_least = 0;      // the value axis reaches at least this (1: reflectance)
  bool log_scale = false;         // value axis in decades (values <= 0 drawn at the bottom)
  std::vector<PlotCurve> curves;  // at most kMaxPlotCurves
  std::vector<std::string> swatch_labels;  // column headings of the swatches, e.g. "input"
  std::vector<std::string> notes;          // small lines under the legend
};

/// The colour spaces of a plot, from the OCIO config's roles: `encoded`, the display-referred
/// space its colours are drawn in (8-bit formats, SVG), and `linear`, the one OpenEXR and
/// Radiance HDR plots are written in.
struct PlotSpaces {
  const ColourSpaces* spaces = nullptr;
  std::string encoded, linear;
};

/// The plot's spaces in `spaces`: the color_picking role, else matte_paint (the shipped
/// 'sRGB - Texture' only for configs without either), and scene_linear (else the shipped
/// 'Linear Rec.709 (sRGB)'); throws ConfigError naming the missing role. Cost: O(spaces).
PlotSpaces plot_spaces(const ColourSpaces& spaces);

/// Size of every plot, raster (pixels) and SVG (user units).
inline constexpr int kPlotWidth = 1000;
inline constexpr int kPlotHeight = 600;
/// The legend has room for this many curves.
inline constexpr std::size_t kMaxPlotCurves = 10;

/// The distinct colour of curve i (the Tableau 10 palette; cycles after 10). Cost: O(1).
PlotColour plot_palette(std::size_t i);

/// True when `path` names a plot: ".svg", or an extension OpenImageIO can write (.png, .jpg,
/// .tif, .exr, ...). Cost: a plugin lookup, ~us once loaded.
bool is_plot_path(const std::string& path);

/// Throws Error naming the file when `path` cannot hold a plot: an .svg, or a format of the
/// output table (imagefile/output_formats.h) that stores its samples (8-bit RGB; OpenEXR half,
/// Radiance HDR float). Cost: O(formats).
void check_plot_file(const std::string& path);

/// Draws the plot with ImageBufAlgo (supersampled, then filtered down) and writes it in the
/// format of `path`'s extension: 8-bit in `cs.encoded`, or `cs.linear` (converted by OCIO) in
/// half for OpenEXR / float for Radiance HDR, tagged as colour/colour_tags.h says; returns its
/// warnings (a format that cannot say the space). Needs a TrueType font (DejaVu Sans); throws
/// Error naming the file and the reason. Written through imagefile/safe_output.h (never over one of
/// `inputs`). Cost: ~0.2 s, ~40 MB.
std::vector<std::string> write_raster(const SpectrumPlot& plot, const std::string& path,
                                      const PlotSpaces& cs,
                                      std::span<const std::string> inputs = {});

/// Writes the plot as SVG text (one <polyline> per curve, one point per sample), through
/// imagefile/safe_output.h (a stream such as /dev/stdout is written in place). SVG colours are
/// sRGB: returns a warning when `cs.encoded` is not. Throws Error naming the file and the reason.
/// Cost: O(samples), ~ms.
std::vector<std::string> write_svg(const SpectrumPlot& plot, const std::string& path,
                                   const PlotSpaces& cs, std::span<const std::string> inputs = {});

/// write_svg for ".svg" paths, write_raster otherwise; returns their warnings. Cost: theirs.
std::vector<std::string> write_plot(const SpectrumPlot& plot, const std::string& path,
                                    const PlotSpaces& cs, std::span<const std::string> inputs = {});

}  // namespace spectralize
