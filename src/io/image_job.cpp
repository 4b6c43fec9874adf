#include "io/image_job.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/parallel.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <future>
#include <vector>

#include "core/error.h"
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

}  // namespace

ImageReport run_image_job(const ImageJobSettings& job, const ProgressFn& progress,
                          const LogFn& log) {
  const auto t_start = Clock::now();
  ImageReport rep;
  rep.input = job.input;
  rep.output = job.output;

  // Never overwrite the input, never write into a folder that is not there.
  std::error_code ec;
  if (!fs::exists(job.input, ec)) throw Error("'" + job.input + "': no such file");
  if (fs::is_directory(job.input, ec)) throw Error("'" + job.input + "': is a directory");
  const fs::path out_path(job.output);
  const fs::path out_dir = out_path.has_parent_path() ? out_path.parent_path() : fs::path(".");
  if (!fs::is_directory(out_dir, ec))
    throw Error("'" + job.output + "': the folder '" + out_dir.string() + "' does not exist");
  if (fs::exists(out_path, ec) && fs::equivalent(out_path, job.input, ec))
    throw Error("'" + job.output + "': is the input file; refusing to overwrite it");

  // Open the input.
  auto in = OIIO::ImageInput::open(job.input);
  if (!in) {
    std::string why = OIIO::geterror();
    throw Error("'" + job.input + "': cannot read: " + (why.empty() ? "unknown format" : why));
  }
  const OIIO::ImageSpec spec = in->spec();
  // --threads bounds our loops and OIIO's own pool (OpenEXR's compression threads included).
  if (job.threads > 0) {
    OIIO::attribute("threads", job.threads);
    OIIO::attribute("exr_threads", job.threads);
  }
  SpectralConverter converter(job, spec, in->format_name(), log, rep);
  const OIIO::ImageSpec& ospec = converter.output_spec();
  const int nch = converter.input_channels(), out_nch = converter.output_channels();

  TemporaryFile tmp;
  tmp.path = (out_dir / ("." + out_path.filename().string() + ".spectralize-" +
                         std::to_string(::getpid()) + ".tmp.exr"))
                 .string();
  auto out = OIIO::ImageOutput::create("openexr");
  if (!out) throw Error("OpenImageIO has no OpenEXR writer: " + OIIO::geterror());
  if (job.tile > 0 && !out->supports("tiles"))
    throw Error("the OpenEXR writer does not support tiles");
  if (!out->open(tmp.path, ospec))
    throw Error("'" + job.output + "': cannot write: " + out->geterror());
  rep.seconds_setup = seconds_since(t_start);

  // Stream strips of rows: read, convert, write. Memory is O(strip), not O(image).
  // A strip holds ~24 MB of output samples, in whole ZIP blocks (16 rows) or tiles, so that
  // OpenEXR compresses many blocks of a strip in parallel while we compute the next strip.
  const std::size_t width = static_cast<std::size_t>(spec.width);
  const int unit = job.tile > 0 ? job.tile : 16;
  const std::size_t bytes_per_row = width * static_cast<std::size_t>(out_nch) * sizeof(float);
  const int strip = unit * static_cast<int>(std::clamp<std::size_t>(
                               (24u << 20) / (bytes_per_row * unit), 1, std::max(1, 512 / unit)));
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
    if (!in->read_scanlines(0, 0, spec.y + y0, spec.y + y1, 0, 0, nch, OIIO::TypeFloat,
                            inbuf.data()))
      throw Error("'" + job.input + "': cannot read rows " + std::to_string(y0) + ".." +
                  std::to_string(y1 - 1) + ": " + in->geterror());
    converter.convert(inbuf.data(), n, outbuf.data());
    auto t1 = Clock::now();
    t_convert += std::chrono::duration<double>(t1 - t0).count();
    // Hand the strip to the writer once it has finished the previous one (two buffers).
    if (writing.valid()) writing.get();
    t_write += seconds_since(t1);
    writing = std::async(std::launch::async, [&, y0, y1, data = outbuf.data()] {
      const bool ok =
          job.tile > 0 ? out->write_tiles(spec.x, spec.x + spec.width, spec.y + y0, spec.y + y1, 0,
                                          1, OIIO::TypeFloat, data)
                       : out->write_scanlines(spec.y + y0, spec.y + y1, 0, OIIO::TypeFloat, data);
      if (!ok) throw Error("'" + job.output + "': write failed: " + out->geterror());
    });
    if (progress) progress(width * y1, width * spec.height);
  }
  auto t_close = Clock::now();
  if (writing.valid()) writing.get();
  if (!out->close()) throw Error("'" + job.output + "': write failed: " + out->geterror());
  in->close();
  fs::rename(tmp.path, job.output, ec);
  if (ec)
    throw Error("'" + job.output + "': cannot move the finished file into place: " + ec.message());
  tmp.keep = true;
  t_write += seconds_since(t_close);

  converter.finish(rep, log);
  rep.pixels = static_cast<std::uint64_t>(spec.width) * spec.height;
  rep.seconds_convert = t_convert;
  rep.seconds_write_close = t_write;
  rep.seconds_total = seconds_since(t_start);
  return rep;
}

}  // namespace spectralize
