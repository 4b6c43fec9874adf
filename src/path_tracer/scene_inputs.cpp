#include "path_tracer/scene_inputs.h"

#include <OpenImageIO/imageio.h>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"

namespace spectralize::path_tracer {

namespace {

constexpr std::string_view kCheckerFile = "colorchecker_n_ohta_5nm.csv";
constexpr int kPatch = 16, kGutter = 2, kColumns = 6, kRows = 4;

}  // namespace

RgbImage read_linear_rgb(const std::string& path, const std::string& file_space,
                         const std::string& linear_space, const ColourSpaces& spaces) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error("cannot read '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw Error("'" + path + "': not an RGB image");
  RgbImage img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, img.rgb.data()))
    throw Error("cannot read '" + path + "': " + in->geterror());
  const std::size_t n = img.rgb.size() / 3;
  spaces.to_xyz(file_space).apply(img.rgb.data(), n);
  spaces.from_xyz(linear_space).apply(img.rgb.data(), n);
  return img;
}

std::vector<Xyz> texel_xyz(const RgbImage& image, const figures::Mat3& m) {
  std::vector<Xyz> out(image.rgb.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = figures::mul(m, {image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]});
  return out;
}

int colorchecker_patch(int x, int y) {
  const int step = kPatch + kGutter;
  const int cx = (x - kGutter) / step, cy = (y - kGutter) / step;
  if (x < kGutter || y < kGutter || cx >= kColumns || cy >= kRows) return -1;
  if ((x - kGutter) % step >= kPatch || (y - kGutter) % step >= kPatch) return -1;
  return cy * kColumns + cx;
}

SampledSpectra measured_colorchecker(int width, int height) {
  constexpr int kWidth = kColumns * kPatch + (kColumns + 1) * kGutter;
  constexpr int kHeight = kRows * kPatch + (kRows + 1) * kGutter;
  if (width != kWidth || height != kHeight)
    throw Error("the ColorChecker chart is " + std::to_string(kWidth) + " x " +
                std::to_string(kHeight) + " texels, not " + std::to_string(width) + " x " +
                std::to_string(height));
  const std::vector<std::string> names = embedded_columns(kCheckerFile);
  std::vector<float> spectra;
  std::vector<double> nm;
  for (const std::string& name : names) {
    const auto [wl, values] = embedded_column(kCheckerFile, name);
    nm = wl;
    for (const double v : values) spectra.push_back(static_cast<float>(v));
  }
  const std::size_t bands = nm.size();
  const std::uint32_t black = static_cast<std::uint32_t>(names.size());
  spectra.resize(spectra.size() + bands, 0.0f);  // the gutter
  std::vector<std::uint32_t> index(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int p = colorchecker_patch(x, y);
      index[static_cast<std::size_t>(y) * width + x] =
          p < 0 ? black : static_cast<std::uint32_t>(p);
    }
  return SampledSpectra(static_cast<float>(nm.front()), static_cast<float>(nm[1] - nm[0]), bands,
                        std::move(spectra), std::move(index));
}

std::vector<float> unit_illuminant(const std::string& name, Xyz* xyz) {
  const Illuminant e = Illuminant::get(name);
  const Observer& o = Observer::get("cie1931");
  Xyz sum;
  for (std::size_t k = 0; k < ReferenceTable::kSize; ++k) {
    const double w = ReferenceTable::trapezoid(k) * e.spd[k] / o.y_integral;
    sum = sum + w * Xyz{o.cmf[0][k], o.cmf[1][k], o.cmf[2][k]};
  }
  std::vector<float> out(ReferenceTable::kSize);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = static_cast<float>(e.spd[k] / sum.Y);
  if (xyz) *xyz = (1 / sum.Y) * sum;
  return out;
}

}  // namespace spectralize::path_tracer
