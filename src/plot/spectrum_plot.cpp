#include "plot/spectrum_plot.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string_view>
#include <utility>

#include "colour/colour_space.h"
#include "colour/colour_tags.h"
#include "imagefile/image_file_output.h"
#include "imagefile/oiio_compat.h"
#include "imagefile/output_formats.h"
#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

// --- Layout, in output pixels (SVG user units) ---
constexpr double kLeft = 80, kRight = 716, kTop = 100, kBottom = 528;  // the plot area
constexpr double kLegendLeft = 740, kLegendRight = 988;
constexpr int kSupersample = 3;  // raster: drawn at 3x, then box-filtered down (antialiasing)

constexpr PlotColour kWhite{1, 1, 1}, kInk{0.13f, 0.13f, 0.13f}, kGrey{0.4f, 0.4f, 0.4f};
constexpr PlotColour kGridGrey{0.88f, 0.88f, 0.88f}, kFrame{0.2f, 0.2f, 0.2f};

struct Point {
  double x, y;
};
enum class Align { left, center, right };

// The drawing operations the layout needs; a raster and an SVG implementation.
class Painter {
 public:
  virtual ~Painter() = default;
  virtual void line(Point a, Point b, PlotColour c, double width) = 0;
  virtual void fill_rect(double x, double y, double w, double h, PlotColour c) = 0;
  // Text with its baseline at y.
  virtual void text(Point at, std::string_view s, double size, PlotColour c, Align align) = 0;
  virtual void polyline(std::span<const Point> points, PlotColour c, double width) = 0;
  virtual void markers(std::span<const Point> points, PlotColour c, double radius) = 0;
  virtual void begin_group(std::string_view /*id*/) {}
  virtual void end_group() {}
};

// --- Axis ticks ---

// A "nice" step (1, 2, 2.5 or 5 times a power of ten) giving about `target` intervals.
double nice_step(double range, int target) {
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double nice = f <= 1 ? 1 : f <= 2 ? 2 : f <= 2.5 ? 2.5 : f <= 5 ? 5 : 10;
  return nice * mag;
}

struct Axis {
  double lo, hi, step;
  // Tick values from the first multiple of step at or above lo to hi.
  std::vector<double> ticks() const {
    std::vector<double> t;
    const double first = std::ceil(lo / step - 1e-9) * step;
    for (int i = 0;; ++i) {
      const double v = first + i * step;
      if (v > hi + step * 1e-9) break;
      t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    }
    return t;
  }
  // Labels with as many decimals as the step needs (2.5e-3 -> 4), or %g for extreme scales.
  std::string label(double v) const {
    if (std::max(std::abs(lo), std::abs(hi)) >= 1e6 || step < 1e-4) return fmt::format("{:g}", v);
    int decimals = 0;
    while (decimals < 6 && std::abs(step * std::pow(10.0, decimals) -
                                    std::round(step * std::pow(10.0, decimals))) > 1e-6)
      ++decimals;
    return fmt::format("{:.{}f}", v, decimals);
  }
};

// The wavelength axis spans the data exactly; ticks fall on nice wavelengths inside it.
Axis wavelength_axis(const SpectrumPlot& plot) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& c : plot.curves)
    if (!c.wavelengths.empty()) {
      lo = std::min(lo, c.wavelengths.front());
      hi = std::max(hi, c.wavelengths.back());
    }
  if (!(lo < hi)) {  // no curve or a single wavelength: show the visible range
    lo = std::isfinite(lo) ? lo - 10 : 380;
    hi = std::isfinite(hi) ? hi + 10 : 780;
  }
  return {lo, hi, nice_step(hi - lo, 8)};
}

// The value axis starts at 0 (or below, for negative samples) and ends on a nice tick at or
// above the largest value (and y_top_at_least).
Axis value_axis(const SpectrumPlot& plot) {
  double lo = 0, hi = plot.y_top_at_least;
  for (const auto& c : plot.curves)
    for (double v : c.values)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > lo)) hi = lo + 1;  // all zero (black): a unit axis
  const double step = nice_step(hi - lo, 6);
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step, step};
}

// Log scale: whole decades from the smallest positive value (at most 8 decades below the
// largest) to the largest; ticks and labels are powers of ten.
Axis log_value_axis(const SpectrumPlot& plot) {
  double lo = INFINITY, hi = 0;
  for (const auto& c : plot.curves)
    for (double v : c.values)
      if (std::isfinite(v) && v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > 0)) return {0, 1, 1};
  const double top = std::ceil(std::log10(hi) - 1e-9);
  const double bottom = std::max(std::floor(std::log10(lo) + 1e-9), top - 8);
  return {bottom, top > bottom ? top : bottom + 1, 1};
}

// Cuts text to about `width` units (DejaVu Sans averages ~0.58 em per character).
std::string fit(const std::string& s, double width, double size) {
  const std::size_t max_chars = static_cast<std::size_t>(width / (0.58 * size));
  if (s.size() <= max_chars || max_chars < 4) return s;
  std::size_t cut = max_chars - 3;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
  return s.substr(0, cut) + "...";
}

// --- The layout: one function draws every plot on either painter ---
void draw(const SpectrumPlot& plot, Painter& p) {
  p.fill_rect(0, 0, kPlotWidth, kPlotHeight, kWhite);

  // Title: up to three lines, the first larger.
  p.begin_group("title");
  for (std::size_t i = 0; i < plot.title.size() && i < 3; ++i) {
    const double size = i == 0 ? 18 : 12.5;
    p.text({kLeft - 60, i == 0 ? 28.0 : 34.0 + 18.0 * i}, fit(plot.title[i], kPlotWidth - 40, size),
           size, i == 0 ? kInk : kGrey, Align::left);
  }
  p.end_group();

  const Axis ax = wavelength_axis(plot);
  const Axis ay = plot.log_scale ? log_value_axis(plot) : value_axis(plot);
  auto to_x = [&](double nm) { return kLeft + (nm - ax.lo) / (ax.hi - ax.lo) * (kRight - kLeft); };
  auto to_y = [&](double v) {
    // In decades, values at or below the bottom decade sit on the axis.
    if (plot.log_scale) v = v > 0 ? std::max(std::log10(v), ay.lo) : ay.lo;
    return kBottom - (v - ay.lo) / (ay.hi - ay.lo) * (kBottom - kTop);
  };

  // Grid, ticks and their labels.
  p.begin_group("axes");
  for (double t : ax.ticks()) {
    const double x = to_x(t);
    p.line({x, kTop}, {x, kBottom}, kGridGrey, 1);
    p.line({x, kBottom}, {x, kBottom + 5}, kFrame, 1);
    p.text({x, kBottom + 20}, ax.label(t), 12, kInk, Align::center);
  }
  for (double t : ay.ticks()) {
    const double y = to_y(plot.log_scale ? std::pow(10.0, t) : t);
    p.line({kLeft, y}, {kRight, y}, t == 0 && !plot.log_scale ? kGrey : kGridGrey, 1);
    p.line({kLeft - 5, y}, {kLeft, y}, kFrame, 1);
    p.text({kLeft - 8, y + 4.5},
           plot.log_scale ? fmt::format("{:g}", std::pow(10.0, t)) : ay.label(t), 12, kInk,
           Align::right);
  }
  p.line({kLeft, kTop}, {kRight, kTop}, kFrame, 1);
  p.line({kLeft, kBottom}, {kRight, kBottom}, kFrame, 1);
  p.line({kLeft, kTop}, {kLeft, kBottom}, kFrame, 1);
  p.line({kRight, kTop}, {kRight, kBottom}, kFrame, 1);
  p.text({(kLeft + kRight) / 2, kBottom + 46}, plot.x_label, 13, kInk, Align::center);
  p.text({kLeft - 60, kTop - 10}, fit(plot.y_label, kRight - kLeft + 60, 12), 12, kInk,
         Align::left);
  p.end_group();

  // Curves: the piecewise-linear spectrum and its samples.
  for (std::size_t i = 0; i < plot.curves.size(); ++i) {
    const PlotCurve& c = plot.curves[i];
    std::vector<Point> pts;
    for (std::size_t k = 0; k < c.wavelengths.size() && k < c.values.size(); ++k)
      pts.push_back({to_x(c.wavelengths[k]), to_y(std::isfinite(c.values[k]) ? c.values[k] : 0)});
    if (pts.empty()) continue;
    // Points shrink on dense grids so they do not merge into a band.
    const double spacing = pts.size() > 1 ? (pts.back().x - pts.front().x) / (pts.size() - 1) : 8;
    p.begin_group("curve-" + std::to_string(i + 1));
    p.polyline(pts, c.colour, 2);
    p.markers(pts, c.colour, std::clamp(spacing * 0.3, 0.8, 2.6));
    p.end_group();
  }

  // Legend: per curve a line sample and its label, then its swatches side by side.
  p.begin_group("legend");
  const std::size_t n = std::min(plot.curves.size(), kMaxPlotCurves);
  const std::size_t columns = plot.swatch_labels.size();
  const double col_w = columns ? (kLegendRight - kLegendLeft - 6.0 * (columns - 1)) / columns : 0;
  double y = kTop;
  for (std::size_t s = 0; s < columns; ++s)
    p.text({kLegendLeft + s * (col_w + 6), y + 8}, fit(plot.swatch_labels[s], col_w, 11), 11, kGrey,
           Align::left);
  if (columns) y += 16;
  const double notes_h = 16.0 * plot.notes.size();
  const double entry_h =
      n ? std::min(columns ? 48.0 : 24.0, (kPlotHeight - 12 - notes_h - y) / n) : 0;
  for (std::size_t i = 0; i < n; ++i) {
    const PlotCurve& c = plot.curves[i];
    const double top = y + entry_h * i;
    p.line({kLegendLeft, top + 9}, {kLegendLeft + 24, top + 9}, c.colour, 2.5);
    const Point mid{kLegendLeft + 12, top + 9};
    p.markers(std::span<const Point>(&mid, 1), c.colour, 2.6);
    p.text({kLegendLeft + 32, top + 13.5}, fit(c.label, kLegendRight - kLegendLeft - 32, 12), 12,
           kInk, Align::left);
    const double sh = std::max(6.0, entry_h - 26);
    for (std::size_t s = 0; s < columns && s < c.swatches.size(); ++s) {
      const double x = kLegendLeft + s * (col_w + 6);
      p.fill_rect(x, top + 19, col_w, sh, kGrey);  // a 1-unit frame: white shows on white
      p.fill_rect(x + 1, top + 20, col_w - 2, sh - 2, c.swatches[s]);
    }
  }
  for (std::size_t k = 0; k < plot.notes.size(); ++k)
    p.text({kLegendLeft, kPlotHeight - 12 - notes_h + 16.0 * k + 11},
           fit(plot.notes[k], kPlotWidth - kLegendLeft - 4, 10.5), 10.5, kGrey, Align::left);
  p.end_group();
}

// --- Raster: OIIO's ImageBufAlgo render functions on a supersampled float RGB image ---

class RasterPainter final : public Painter {
 public:
  RasterPainter(OIIO::ImageBuf& buf, std::string font) : buf_(buf), font_(std::move(font)) {}

  void line(Point a, Point b, PlotColour c, double width) override {
    // render_line draws 1 pixel wide: a square brush of parallel lines gives the width.
    const int t = std::max(1, static_cast<int>(std::lround(width * kSupersample)));
    const int x1 = px(a.x), y1 = px(a.y), x2 = px(b.x), y2 = px(b.y);
    for (int dy = -(t - 1) / 2; dy <= t / 2; ++dy)
      for (int dx = -(t - 1) / 2; dx <= t / 2; ++dx)
        OIIO::ImageBufAlgo::render_line(buf_, x1 + dx, y1 + dy, x2 + dx, y2 + dy, rgb(c));
  }
  void fill_rect(double x, double y, double w, double h, PlotColour c) override {
    OIIO::ImageBufAlgo::render_box(buf_, px(x), px(y), px(x + w) - 1, px(y + h) - 1, rgb(c), true);
  }
  void text(Point at, std::string_view s, double size, PlotColour c, Align align) override {
    const auto ax = align == Align::left     ? OIIO::ImageBufAlgo::TextAlignX::Left
                    : align == Align::center ? OIIO::ImageBufAlgo::TextAlignX::Center
                                             : OIIO::ImageBufAlgo::TextAlignX::Right;
    if (!OIIO::ImageBufAlgo::render_text(buf_, px(at.x), px(at.y), ascii(s),
                                         static_cast<int>(std::lround(size * kSupersample)), font_,
                                         rgb(c), ax, OIIO::ImageBufAlgo::TextAlignY::Baseline))
      throw Error("cannot draw text with the font '" + font_ + "': " + buf_.geterror());
  }
  void polyline(std::span<const Point> points, PlotColour c, double width) override {
    for (std::size_t i = 1; i < points.size(); ++i) line(points[i - 1], points[i], c, width);
  }
  void markers(std::span<const Point> points, PlotColour c, double radius) override {
    for (const Point& q : points) fill_rect(q.x - radius, q.y - radius, 2 * radius, 2 * radius, c);
  }

 private:
  static int px(double v) { return static_cast<int>(std::lround(v * kSupersample)); }
  // OIIO 2.4's render_text garbles non-ASCII UTF-8 (it drops the high bit of each byte, also in
  // oiiotool --text): show each non-ASCII character as '?' instead.
  static std::string ascii(std::string_view s) {
    std::string out;
    for (char ch : s) {
      const auto u = static_cast<unsigned char>(ch);
      if (u < 0x80)
        out += ch;
      else if ((u & 0xC0) != 0x80)  // the lead byte of a multi-byte character
        out += '?';
    }
    return out;
  }
  std::array<float, 3> colour_;
  OIIO::cspan<float> rgb(PlotColour c) {
    colour_ = {c.r, c.g, c.b};
    return OIIO::cspan<float>(colour_.data(), 3);
  }
  OIIO::ImageBuf& buf_;
  std::string font_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

// --- SVG: the same layout as text ---

std::string xml_escape(std::string_view s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

std::string hex(PlotColour c) {
  auto byte = [](float v) {
    return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255));
  };
  return fmt::format("#{:02x}{:02x}{:02x}", byte(c.r), byte(c.g), byte(c.b));
}

class SvgPainter final : public Painter {
 public:
  std::string body;
  void line(Point a, Point b, PlotColour c, double width) override {
    fmt::format_to(std::back_inserter(body),
                   "{}<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
                   "stroke-width=\"{:g}\"/>\n",
                   indent(), a.x, a.y, b.x, b.y, hex(c), width);
  }
  void fill_rect(double x, double y, double w, double h, PlotColour c) override {
    fmt::format_to(std::back_inserter(body),
                   "{}<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" "
                   "fill=\"{}\"/>\n",
                   indent(), x, y, w, h, hex(c));
  }
  void text(Point at, std::string_view s, double size, PlotColour c, Align align) override {
    const char* anchor = align == Align::left ? "start" : align == Align::center ? "middle" : "end";
    fmt::format_to(std::back_inserter(body),
                   "{}<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"{:g}\" fill=\"{}\" "
                   "text-anchor=\"{}\">{}</text>\n",
                   indent(), at.x, at.y, size, hex(c), anchor, xml_escape(s));
  }
  void polyline(std::span<const Point> points, PlotColour c, double width) override {
    std::string pts;
    for (const Point& q : points)
      fmt::format_to(std::back_inserter(pts), "{}{:.2f},{:.2f}", pts.empty() ? "" : " ", q.x, q.y);
    fmt::format_to(std::back_inserter(body),
                   "{}<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{:g}\" "
                   "stroke-linejoin=\"round\" points=\"{}\"/>\n",
                   indent(), hex(c), width, pts);
  }
  void markers(std::span<const Point> points, PlotColour c, double radius) override {
    fmt::format_to(std::back_inserter(body), "{}<g fill=\"{}\">\n", indent(), hex(c));
    for (const Point& q : points)
      fmt::format_to(std::back_inserter(body),
                     "{}  <circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:g}\"/>\n", indent(), q.x, q.y,
                     radius);
    fmt::format_to(std::back_inserter(body), "{}</g>\n", indent());
  }
  void begin_group(std::string_view id) override {
    fmt::format_to(std::back_inserter(body), "{}<g id=\"{}\">\n", indent(), xml_escape(id));
    ++depth_;
  }
  void end_group() override {
    --depth_;
    fmt::format_to(std::back_inserter(body), "{}</g>\n", indent());
  }

 private:
  std::string indent() const { return std::string(2 * (depth_ + 1), ' '); }
  int depth_ = 0;
};

}  // namespace

PlotColour plot_palette(std::size_t i) {
  // Tableau 10: distinct hues of similar weight, readable on white.
  static constexpr std::array<std::array<int, 3>, 10> kTableau = {{{31, 119, 180},
                                                                   {255, 127, 14},
                                                                   {44, 160, 44},
                                                                   {214, 39, 40},
                                                                   {148, 103, 189},
                                                                   {140, 86, 75},
                                                                   {227, 119, 194},
                                                                   {127, 127, 127},
                                                                   {188, 189, 34},
                                                                   {23, 190, 207}}};
  const auto& c = kTableau[i % kTableau.size()];
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
}

PlotSpaces plot_spaces(const ColourSpaces& spaces) {
  PlotSpaces cs;
  cs.spaces = &spaces;
  cs.encoded = spaces.role_or_name({"color_picking", "matte_paint"}, {"sRGB - Texture"},
                                   "the display-referred colours of a plot");
  cs.linear =
      spaces.role_or_name({"scene_linear"}, {kDefaultColourSpace}, "the linear light of a plot");
  return cs;
}

bool is_plot_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".svg") return true;
  if (ext.size() < 2) return false;
  auto out = OIIO::ImageOutput::create(ext.substr(1));
  if (!out) {
    (void)OIIO::geterror();  // clear OIIO's "no writer for ..." message
    return false;
  }
  return true;
}

// The samples a raster plot is written in, from the output table: 8-bit encoded colours where
// the format holds them, else half or float (OpenEXR, Radiance HDR), whose convention is linear
// light.
OIIO::TypeDesc plot_sample_type(const OutputFormat* f) {
  if (!f || f->holds("uint8")) return OIIO::TypeUInt8;
  return f->holds("half") ? OIIO::TypeHalf : OIIO::TypeFloat;
}

void check_plot_file(const std::string& path) {
  if (lower_extension(path) == ".svg") return;
  OutputRequest want;
  want.samples = sample_type_name(plot_sample_type(output_format_for(path)));
  check_output(path, want, "");
}

std::vector<std::string> write_raster(const SpectrumPlot& plot, const std::string& path,
                                      const PlotSpaces& cs, std::span<const std::string> inputs) {
  check_plot_file(path);  // before any drawing
  const std::string font = find_font();
  if (font.empty())
    throw Error("'" + path +
                "': no font to draw the plot's text: install DejaVu Sans (Debian: apt-get "
                "install fonts-dejavu-core, which puts DejaVuSans.ttf in "
                "/usr/share/fonts/truetype/dejavu/), or write an .svg plot");
  auto writer = OIIO::ImageOutput::create(path);
  if (!writer) {
    (void)OIIO::geterror();
    throw Error("'" + path + "': OpenImageIO cannot write this file type; use .png or .svg");
  }
  const std::string format = writer->format_name();
  writer.reset();

  // Draw at kSupersample x the size, then average kSupersample^2 pixels per output pixel.
  // Half samples: 32 MB instead of 65, and exact for 8-bit output.
  OIIO::ImageBuf big(
      OIIO::ImageSpec(kPlotWidth * kSupersample, kPlotHeight * kSupersample, 3, OIIO::TypeHalf));
  RasterPainter painter(big, font);
  draw(plot, painter);
  OIIO::ImageBuf small = box_resize(big, OIIO::ROI(0, kPlotWidth, 0, kPlotHeight, 0, 1, 0, 3));
  if (small.has_error()) throw Error("'" + path + "': cannot filter the plot: " + small.geterror());

  // The drawing's encoded space for 8-bit formats; the linear space for the others (OpenEXR,
  // Radiance HDR), whose convention is linear light (converted by OCIO).
  const OIIO::TypeDesc type = plot_sample_type(output_format_named(format));
  std::string space = cs.encoded;
  if (type != OIIO::TypeUInt8) {
    space = cs.linear;
    OIIO::ImageBuf linear;
    linear.copy(small, OIIO::TypeFloat);
    small = std::move(linear);
    std::vector<float> rgb(static_cast<std::size_t>(kPlotWidth) * kPlotHeight * 3);
    small.get_pixels(OIIO::ROI::All(), OIIO::TypeFloat, rgb.data());
    for (float& v : rgb) v = std::clamp(v, 0.0f, 1.0f);
    cs.spaces->to_xyz(cs.encoded).apply(rgb.data(), rgb.size() / 3);
    cs.spaces->from_xyz(cs.linear).apply(rgb.data(), rgb.size() / 3);
    small.set_pixels(OIIO::ROI::All(), OIIO::TypeFloat, rgb.data());
  }
  std::vector<std::string> warnings =
      tag_colour_space(small.specmod(), *cs.spaces, space, format, path);
  small.specmod().attribute("Software", "spectralize " SPECTRALIZE_VERSION);
  write_image_file(small, path, type, inputs);
  return warnings;
}

std::vector<std::string> write_svg(const SpectrumPlot& plot, const std::string& path,
                                   const PlotSpaces& cs, std::span<const std::string> inputs) {
  SvgPainter painter;
  draw(plot, painter);
  std::string title;
  for (const auto& line : plot.title) title += (title.empty() ? "" : " | ") + line;
  const std::string svg = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\" font-family=\"DejaVu Sans, Verdana, Arial, sans-serif\">\n"
      "  <title>{2}</title>\n"
      "{3}</svg>\n",
      kPlotWidth, kPlotHeight, xml_escape(title), painter.body);
  AtomicOutput file(path, WriteRules::named("the plot").streams(), inputs);
  file.write(svg);
  file.commit();
  std::vector<std::string> warnings;
  if (cs.spaces->interop_id(cs.encoded) != "srgb_rec709_scene")
    warnings.push_back(quote(path, 200) +
                       ": SVG colours are sRGB, but the plot's colours are in '" + cs.encoded +
                       "' (the config's display-referred role): they will look wrong");
  return warnings;
}

std::vector<std::string> write_plot(const SpectrumPlot& plot, const std::string& path,
                                    const PlotSpaces& cs, std::span<const std::string> inputs) {
  if (lower_extension(path) == ".svg") return write_svg(plot, path, cs, inputs);
  return write_raster(plot, path, cs, inputs);
}

}  // namespace spectralize
