#include "io/image_job.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/parallel.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <future>
#include <vector>

#include "core/error.h"
#include "io/output_spec.h"
#include "io/rgb_from_spectral.h"
#include "io/spectral_converter.h"

namespace fs = std::filesystem;

namespace spectralize {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Removes the temporary output unless the job committed it.
struct TemporaryFile {
  std::string path;
  bool keep = false;
  ~TemporaryFile() {
    if (!keep && !path.empty()) {
      std::error_code ec;
      fs::remove(path, ec);
    }
  }
};

// Refuses what must not happen (missing input, missing output folder, output equal to the
// input) and opens the input.
std::unique_ptr<OIIO::ImageInput> open_input(const std::string& input, const std::string& output) {
  std::error_code ec;
  if (!fs::exists(input, ec)) throw Error("'" + input + "': no such file");
  if (fs::is_directory(input, ec)) throw Error("'" + input + "': is a directory");
  const fs::path out_path(output);
  const fs::path out_dir = out_path.has_parent_path() ? out_path.parent_path() : fs::path(".");
  if (!fs::is_directory(out_dir, ec))
    throw Error("'" + output + "': the folder '" + out_dir.string() + "' does not exist");
  if (fs::exists(out_path, ec) && fs::equivalent(out_path, input, ec))
    throw Error("'" + output + "': is the input file; refusing to overwrite it");
  auto in = OIIO::ImageInput::open(input);
  if (!in) {
    std::string why = OIIO::geterror();
    throw Error("'" + input + "': cannot read: " + (why.empty() ? "unknown format" : why));
  }
  return in;
}

// --threads bounds our loops and OIIO's own pool (OpenEXR's compression threads included).
void limit_threads(int threads) {
  if (threads > 0) {
    OIIO::attribute("threads", threads);
    OIIO::attribute("exr_threads", threads);
  }
}

using RowsFn = std::function<void(const float* in, std::size_t pixels, float* out)>;

// Streams the input to an OpenEXR of `ospec` in strips: read, convert, write (the write of one
// strip overlapping the conversion of the next), through a temporary file beside the output,
// renamed when complete. Memory is O(strip), not O(image). Returns (convert, write) seconds.
std::pair<double, double> stream(OIIO::ImageInput& in, const std::string& input,
                                 const std::string& output, const OIIO::ImageSpec& ospec, int tile,
                                 const RowsFn& convert, const ProgressFn& progress) {
  const OIIO::ImageSpec& spec = in.spec();
  const int nch = spec.nchannels, out_nch = ospec.nchannels;
  const fs::path out_path(output);
  const fs::path out_dir = out_path.has_parent_path() ? out_path.parent_path() : fs::path(".");
  TemporaryFile tmp;
  tmp.path = (out_dir / ("." + out_path.filename().string() + ".spectralize-" +
                         std::to_string(::getpid()) + ".tmp.exr"))
                 .string();
  auto out = OIIO::ImageOutput::create("openexr");
  if (!out) throw Error("OpenImageIO has no OpenEXR writer: " + OIIO::geterror());
  if (!out->open(tmp.path, ospec))
    throw Error("'" + output + "': cannot write: " + out->geterror());

  // A strip holds ~24 MB of output samples, in whole ZIP blocks (16 rows) or tiles, so that
  // OpenEXR compresses many blocks of a strip in parallel while we compute the next strip.
  // Very wide scanline images go a row at a time (OpenEXR gathers its blocks itself), so
  // memory stays bounded whatever the width.
  const std::size_t width = static_cast<std::size_t>(spec.width);
  const std::size_t bytes_per_row = width * static_cast<std::size_t>(out_nch) * sizeof(float);
  const std::size_t budget = 24u << 20;
  const int unit = tile > 0 ? tile : (bytes_per_row * 16 > budget ? 1 : 16);
  const int strip = unit * static_cast<int>(std::clamp<std::size_t>(budget / (bytes_per_row * unit),
                                                                    1, std::max(1, 512 / unit)));
  std::vector<float> inbuf(width * strip * nch);
  std::vector<float> outbufs[2] = {std::vector<float>(width * strip * out_nch),
                                   std::vector<float>(width * strip * out_nch)};
  std::future<void> writing;  // the previous strip's write, overlapping this strip's work
  double t_convert = 0, t_write = 0;
  for (int y0 = 0, k = 0; y0 < spec.height; y0 += strip, ++k) {
    const int y1 = std::min(spec.height, y0 + strip);
    std::vector<float>& outbuf = outbufs[k % 2];
    const std::size_t n = width * static_cast<std::size_t>(y1 - y0);
    auto t0 = Clock::now();
    if (!in.read_scanlines(0, 0, spec.y + y0, spec.y + y1, 0, 0, nch, OIIO::TypeFloat,
                           inbuf.data()))
      throw Error("'" + input + "': cannot read rows " + std::to_string(y0) + ".." +
                  std::to_string(y1 - 1) + ": " + in.geterror());
    convert(inbuf.data(), n, outbuf.data());
    auto t1 = Clock::now();
    t_convert += std::chrono::duration<double>(t1 - t0).count();
    // Hand the strip to the writer once it has finished the previous one (two buffers).
    if (writing.valid()) writing.get();
    t_write += seconds_since(t1);
    writing = std::async(std::launch::async, [&, y0, y1, data = outbuf.data()] {
      const bool ok =
          tile > 0 ? out->write_tiles(spec.x, spec.x + spec.width, spec.y + y0, spec.y + y1, 0, 1,
                                      OIIO::TypeFloat, data)
                   : out->write_scanlines(spec.y + y0, spec.y + y1, 0, OIIO::TypeFloat, data);
      if (!ok) throw Error("'" + output + "': write failed: " + out->geterror());
    });
    if (progress) progress(width * y1, width * spec.height);
  }
  auto t_close = Clock::now();
  if (writing.valid()) writing.get();
  if (!out->close()) throw Error("'" + output + "': write failed: " + out->geterror());
  in.close();
  std::error_code ec;
  fs::rename(tmp.path, output, ec);
  if (ec)
    throw Error("'" + output + "': cannot move the finished file into place: " + ec.message());
  tmp.keep = true;
  t_write += seconds_since(t_close);
  return {t_convert, t_write};
}

}  // namespace

ImageReport run_image_job(const ImageJobSettings& job, const ProgressFn& progress,
                          const LogFn& log) {
  const auto t_start = Clock::now();
  ImageReport rep;
  rep.input = job.input;
  rep.output = job.output;
  auto in = open_input(job.input, job.output);
  limit_threads(job.threads);
  SpectralConverter converter(job, in->spec(), in->format_name(), log, rep);
  rep.seconds_setup = seconds_since(t_start);
  auto [t_convert, t_write] = stream(
      *in, job.input, job.output, converter.output_spec(), job.tile,
      [&](const float* src, std::size_t n, float* dst) { converter.convert(src, n, dst); },
      progress);
  converter.finish(rep, log);
  rep.pixels = static_cast<std::uint64_t>(rep.width) * rep.height;
  rep.seconds_convert = t_convert;
  rep.seconds_write_close = t_write;
  rep.seconds_total = seconds_since(t_start);
  return rep;
}

ToRgbReport run_to_rgb_job(const ToRgbSettings& job, const ProgressFn& progress, const LogFn& log) {
  const auto t_start = Clock::now();
  ToRgbReport rep;
  rep.input = job.input;
  rep.output = job.output;
  auto in = open_input(job.input, job.output);
  limit_threads(job.threads);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0) throw Error("'" + job.input + "': empty image");
  const SpectralLayoutInfo layout = analyse_spectral_layout(spec, job.input);
  const ColourSpaces spaces = ColourSpaces::load(job.config);
  RgbSettings rgb{spaces.resolve(job.colorspace), job.observer, job.illuminant};
  const RgbFromSpectral to_rgb(layout, rgb, spaces);
  rep.colorspace = rgb.colorspace;
  rep.kind = layout.emissive ? "emissive" : "reflective";
  rep.width = spec.width;
  rep.height = spec.height;
  rep.bands = static_cast<int>(layout.wavelengths.size());
  rep.first_nm = layout.wavelengths.front();
  rep.last_nm = layout.wavelengths.back();
  rep.polarised = layout.polarised;
  if (layout.polarised)
    log(1, "'" + job.input + "': polarised: S0 (intensity) used, S1..S3 ignored");

  OIIO::ImageSpec ospec =
      output_spec_like(spec, to_rgb.output_channels(), job.half, layout.alpha >= 0);
  ospec.attribute("compression", job.compression);
  ospec.attribute("Software", "spectralize " SPECTRALIZE_VERSION);
  if (!job.date_time.empty()) ospec.attribute("DateTime", job.date_time);
  ospec.attribute("spectralize:colorspace", rgb.colorspace);
  if (!layout.emissive) ospec.attribute("spectralize:illuminant", job.illuminant);
  const int in_nch = spec.nchannels;
  stream(
      *in, job.input, job.output, ospec, 0,
      [&](const float* src, std::size_t n, float* dst) {
        OIIO::parallel_for_chunked(
            0, static_cast<int64_t>(n), 4096,
            [&](int64_t b, int64_t e) {
              to_rgb.convert(src + b * in_nch, in_nch, static_cast<std::size_t>(e - b),
                             dst + b * to_rgb.output_channels());
            },
            OIIO::paropt(job.threads));
      },
      progress);
  rep.seconds = seconds_since(t_start);
  return rep;
}

}  // namespace spectralize
