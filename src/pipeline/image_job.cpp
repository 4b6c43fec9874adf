#include "pipeline/image_job.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/parallel.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <future>
#include <mutex>
#include <numeric>
#include <optional>
#include <thread>
#include <vector>

#include "colour/colour_space.h"
#include "colour/colour_tags.h"
#include "imagefile/exr_header.h"
#include "imagefile/exr_scanline_writer.h"
#include "imagefile/image_file_output.h"
#include "imagefile/image_reader.h"
#include "imagefile/output_formats.h"
#include "imagefile/output_metadata.h"
#include "imagefile/safe_output.h"
#include "imagefile/strip_plan.h"
#include "pipeline/image_conversion.h"
#include "pipeline/rgb_conversion.h"
#include "pipeline/rgb_from_spectral.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace spectralize {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// --threads bounds our loops and OIIO's own pool (OpenEXR's compression threads included).
void limit_threads(int threads) {
  if (threads > 0) {
    OIIO::attribute("threads", threads);
    OIIO::attribute("exr_threads", threads);
  }
}

using RowsFn = std::function<void(const float* in, std::size_t pixels, float* out)>;

int worker_count(int threads) {
  return threads > 0 ? threads
                     : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Where the strips go. Scanline OpenEXR: ExrScanlineWriter, several whole compression blocks per
// call (compressed in parallel). Tiles and other formats: OIIO's writer. Buffers are in the
// file's own sample type where it is HALF or FLOAT (no conversion copy inside the writer),
// else float (OIIO converts: integer RGB files).
class Sink {
 public:
  Sink(const std::string& format, const OIIO::ImageSpec& ospec, AtomicOutput& file, int threads)
      : file_(file), ospec_(ospec), tiled_(ospec.tile_width > 0) {
    const std::string& output = file.destination();
    const bool uniform = ospec.channelformats.empty();
    type_ = uniform && (ospec.format == OIIO::TypeHalf || ospec.format == OIIO::TypeFloat)
                ? ospec.format
                : OIIO::TypeFloat;
    if (format == "openexr" && !tiled_) {
      exr_ =
          std::make_unique<ExrScanlineWriter>(ospec, file.proxy(), output, worker_count(threads));
      block_ = exr_block_rows(ospec.get_string_attribute("compression", "zip"));
      return;
    }
    writer_ = OIIO::ImageOutput::create(format);
    if (!writer_) throw Error("OpenImageIO has no " + format + " writer: " + OIIO::geterror());
    // Every byte goes through the checked proxy where the writer uses one correctly, so a full
    // disk or a file-size limit is an error here, not a truncated file at the destination.
    const bool proxied = writes_through_proxy(format) && writer_->set_ioproxy(file.proxy());
    if (!writer_->open(proxied ? output : file.path(), ospec))
      throw Error("'" + output + "': cannot write: " + writer_->geterror());
    block_ = tiled_ ? ospec.tile_height : 16;
  }

  /// The sample type of the buffers write() takes. Cost: O(1).
  OIIO::TypeDesc type() const { return type_; }
  /// Rows of one compression block (or tile). Cost: O(1).
  int block_rows() const { return block_; }

  /// Rows [y0, y1) of the data window, relative to its top. Thread: one at a time, in order.
  void write(int y0, int y1, const void* data) {
    const OIIO::ImageSpec& s = ospec_;
    with_system_reason([&] {
      if (exr_) {
        exr_->write(s.y + y0, y1 - y0, data);
      } else {
        const bool ok =
            tiled_ ? writer_->write_tiles(s.x, s.x + s.width, s.y + y0, s.y + y1, 0, 1, type_, data)
                   : writer_->write_scanlines(s.y + y0, s.y + y1, 0, type_, data);
        if (!ok) throw Error("'" + file_.destination() + "': write failed: " + writer_->geterror());
      }
    });
    file_.check();
  }

  /// Why the finished file is not what was meant ("" when it is: its header and chunk table
  /// are written last). Cost: OpenEXR's written by OpenEXR: reading its header and an 8-byte
  /// chunk head per block; other formats: the reader's open.
  std::string problem() const {
    const OIIO::ImageSpec& s = ospec_;
    if (exr_) {
      const std::string why = exr_scanline_problem(file_.path(), s.width, s.height, s.nchannels);
      return why.empty() ? "" : "the written file does not read back: " + why;
    }
    auto back = OIIO::ImageInput::create(writer_->format_name());
    OIIO::ImageSpec got;
    if (!back || !back->open(file_.path(), got))
      return "the written file does not read back: " + (back ? back->geterror() : OIIO::geterror());
    back->close();
    if (got.width != s.width || got.height != s.height || got.nchannels != s.nchannels)
      return "the written file reads back as " + std::to_string(got.width) + "x" +
             std::to_string(got.height) + ", " + std::to_string(got.nchannels) +
             " channels, not the " + std::to_string(s.width) + "x" + std::to_string(s.height) +
             ", " + std::to_string(s.nchannels) + " channels written";
    return "";
  }

  /// Completes the file. Cost: the writer's close.
  void close() {
    with_system_reason([&] {
      if (exr_) {
        exr_->close();
      } else if (!writer_->close()) {
        throw Error("'" + file_.destination() + "': write failed: " + writer_->geterror());
      }
    });
  }

 private:
  // A writer's failure after a write the system refused is reported with the system's reason
  // ("No space left on device"), not the writer's words for it.
  template <class Fn>
  void with_system_reason(Fn&& fn) {
    try {
      fn();
    } catch (const FileError&) {
      throw;
    } catch (const Error& e) {
      file_.fail(e.what(), errno);
    }
  }

  AtomicOutput& file_;
  const OIIO::ImageSpec& ospec_;
  bool tiled_;
  OIIO::TypeDesc type_;
  int block_ = 16;
  std::unique_ptr<ExrScanlineWriter> exr_;
  std::unique_ptr<OIIO::ImageOutput> writer_;
};

// Streams the input to an image of `ospec` in strips: read, convert, write (the write of one
// strip overlapping the conversion of the next), through `file`'s checked temporary file.
// Memory is O(strip), not O(image). Returns (convert, write) seconds.
std::pair<double, double> stream(ImageReader& in, AtomicOutput& file, const std::string& format,
                                 const OIIO::ImageSpec& ospec, const RowsFn& convert,
                                 const ProgressFn& progress, int threads,
                                 const ThreadShare* share = nullptr) {
  const OIIO::ImageSpec& spec = in.spec();
  const std::string& output = file.destination();
  const int nch = spec.nchannels, out_nch = ospec.nchannels;
  // A writer that cannot even start (its header refused by a full disk) says why, too.
  std::unique_ptr<Sink> made;
  try {
    made = std::make_unique<Sink>(format, ospec, file, threads);
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    file.fail(e.what(), errno);
  }
  Sink& sink = *made;
  const std::size_t width = static_cast<std::size_t>(spec.width);
  const std::size_t sample = sink.type().size();
  const int strip =
      strip_rows(spec.height, sink.block_rows(), width * out_nch * sample, worker_count(threads));
  // Rows are converted in pieces of ~0.1 s (at most ~8 MB of float samples; the first piece is
  // one row, then sized from the time the last one took), and progress is told after each: a
  // caller that stops the job is heard within one piece, whatever the method and grid
  // (docs/DESIGN.md §10). The converter writes float; HALF strips are filled through a float
  // scratch buffer of that size (so the strip is never held as float too).
  const bool narrow = sink.type() != OIIO::TypeFloat;
  const int max_sub =
      std::clamp(static_cast<int>((8u << 20) / (width * out_nch * sizeof(float))), 1, strip);
  int sub = 1;
  std::vector<float> inbuf(width * strip * nch);
  std::vector<float> scratch(narrow ? width * max_sub * out_nch : 0);
  // Room after the strip: OIIO 2.4's HEIF writer copies each row with libheif's aligned row
  // stride, reading past a strip's last row (imagefile/output_formats.cpp's probe met it).
  constexpr std::size_t kWriterSlack = 4096;
  std::vector<unsigned char> outbufs[2] = {
      std::vector<unsigned char>(width * strip * out_nch * sample + kWriterSlack),
      std::vector<unsigned char>(width * strip * out_nch * sample + kWriterSlack)};
  std::future<void> writing;  // the previous strip's write, overlapping this strip's work
  double t_convert = 0, t_write = 0;
  for (int y0 = 0, k = 0; y0 < spec.height; y0 += strip, ++k) {
    const int y1 = std::min(spec.height, y0 + strip);
    unsigned char* out = outbufs[k % 2].data();
    auto t0 = Clock::now();
    in.read_rows(y0, y1, inbuf.data());
    for (int r0 = y0, r1 = y0; r0 < y1; r0 = r1) {
      r1 = std::min(y1, r0 + sub);
      const auto piece_start = Clock::now();
      const std::size_t n = width * static_cast<std::size_t>(r1 - r0);
      const float* src = inbuf.data() + width * static_cast<std::size_t>(r0 - y0) * nch;
      unsigned char* dst = out + width * static_cast<std::size_t>(r0 - y0) * out_nch * sample;
      if (!narrow) {
        convert(src, n, reinterpret_cast<float*>(dst));
      } else {
        convert(src, n, scratch.data());
        OIIO::convert_pixel_values(OIIO::TypeFloat, scratch.data(), sink.type(), dst,
                                   static_cast<int>(n * out_nch));
      }
      const double took = seconds_since(piece_start);
      sub = std::clamp(took > 0 ? static_cast<int>(sub * 0.1 / took) : max_sub, 1,
                       std::min(max_sub, 2 * sub));
      if (progress && r1 < y1) progress(width * r1, width * spec.height);
    }
    auto t1 = Clock::now();
    t_convert += std::chrono::duration<double>(t1 - t0).count();
    // Hand the strip to the writer once it has finished the previous one (two buffers). With
    // --threads 1 the write runs here, so the job never keeps more than one core busy.
    if (writing.valid()) writing.get();
    t_write += seconds_since(t1);
    // The last strip too: nothing follows for its write to overlap (a tiny file's only strip).
    if (y1 == spec.height || (share ? share->now() : threads) == 1)
      sink.write(y0, y1, out);
    else
      writing = std::async(std::launch::async, [&sink, y0, y1, out] { sink.write(y0, y1, out); });
    if (progress) progress(width * y1, width * spec.height);
  }
  auto t_close = Clock::now();
  if (writing.valid()) writing.get();
  sink.close();
  // The finished file must be what was meant (its header and chunk table are written last).
  file.check();
  if (const std::string why = sink.problem(); !why.empty()) throw Error("'" + output + "': " + why);
  t_write += seconds_since(t_close);
  return {t_convert, t_write};
}

}  // namespace

ImageReport run_image_job(const JobPlan& plan, const std::string& input, const std::string& output,
                          const ProgressFn& progress, const LogFn& log,
                          const ImageJobOptions& options) {
  install_cleanup_handlers();
  const ReadFileScope reads;  // no output of the job replaces a file it reads
  const auto t_start = Clock::now();
  const Settings& settings = plan.settings;
  std::optional<ImageReader> opened;
  ImageReader& reader = options.reader ? *options.reader
                                       : opened.emplace(input, spectral_output_channels(settings),
                                                        /*straight_alpha=*/true);
  // The destination is checked (and its temporary file created) before any work.
  AtomicOutput file(output, options.output, std::span<const std::string>(&input, 1));
  if (!options.shared.pool) limit_threads(settings.threads);  // a batch sets its threads once
  // The header records the warnings and, filled in at the end, the counts.
  ConversionContext context = options.shared;
  context.record_in_header = true;
  // A batch decides (and keys) its files before it converts them; a single job here.
  const JobPlan decided = plan.decided() ? plan : planned_input(plan, input, reader.spec());
  ImageConversion conversion(decided, reader.spec(), reader.format_name(), reader.straight_alpha(),
                             log, context);
  {
    // What OpenEXR must hold, now that the channels are known (docs/DESIGN.md §9).
    const OIIO::ImageSpec& o = conversion.output_spec();
    OutputRequest want;
    want.samples = sample_type_name(o.format);
    want.compression = settings.compression;
    want.tile_width = settings.tile_width;
    want.tile_height = settings.tile_height;
    want.channels = decided.output_channels;
    check_output(output, want);
  }
  if (reader.mip_levels() > 1 || reader.subimages() > 1)
    log(1, "'" + input + "': " + std::to_string(reader.mip_levels()) + " MIP levels, " +
               std::to_string(reader.subimages()) +
               " subimages: level 0 of the first subimage is converted");
  const double t_setup = seconds_since(t_start);
  auto [t_convert, t_write] = stream(
      reader, file, "openexr", conversion.output_spec(),
      [&](const float* src, std::size_t n, float* dst) { conversion.convert(src, n, dst); },
      progress, settings.threads, options.shared.share);  // a batch's share: asked per strip
  ImageReport rep = conversion.finish(log);
  rep.output = output;
  rep.mip_levels = reader.mip_levels();
  rep.subimages = reader.subimages();
  rep.tiled_input = reader.tile_height() > 0;
  rep.seconds_setup = t_setup;
  rep.seconds_convert = t_convert;
  rep.seconds_write = t_write;
  rep.seconds_total = seconds_since(t_start);
  // The counts into the doubles the header holds for them (same size: nothing moves).
  const auto extents = exr_attribute_extents(file.path());
  for (const auto& [name, value] : count_attributes(rep.counts)) {
    auto it = extents.find("spectralize:" + name);
    if (it == extents.end() || it->second.second != sizeof value)
      throw FileError(quote(output, 200) + ": the written header lost its " + name + " record");
    file.overwrite(it->second.first,
                   std::string_view(reinterpret_cast<const char*>(&value), sizeof value));
  }
  // What must succeed with the image (its report) is written first: a failure there leaves
  // nothing at the destination either.
  if (options.before_commit) options.before_commit(rep);
  file.commit();
  return rep;
}

ToRgbReport run_to_rgb_job(const JobPlan& plan, const std::string& input, const std::string& output,
                           const ProgressFn& progress, const LogFn& log,
                           const std::function<void(const ToRgbReport&)>& before_commit) {
  install_cleanup_handlers();
  const ReadFileScope reads;  // no output of the job replaces a file it reads
  const auto t_start = Clock::now();
  const Settings& settings = plan.settings;
  ImageReader reader(input, 4);
  const OIIO::ImageSpec& spec = reader.spec();
  const JobPlan decided = planned_input(plan, input, spec);
  // What the output's format holds, checked before any work (docs/DESIGN.md §9): the sample
  // type, compression, tiles, and alpha if the file has it.
  OutputRequest want;
  want.samples = sample_type_name(rgb_sample_type(settings));
  want.compression = settings.compression;
  want.tile_width = settings.tile_width;
  want.tile_height = settings.tile_height;
  want.channels = decided.output_channels;
  want.alpha = decided.spectral.alpha >= 0;
  const OutputFormat& format = check_output(output, want);
  AtomicOutput file(output, WriteRules::named("the output"),
                    std::span<const std::string>(&input, 1));
  limit_threads(settings.threads);
  RgbConversion conversion(decided, spec, output, &format, log);
  stream(
      reader, file, std::string(format.name), conversion.output_spec(),
      [&](const float* src, std::size_t n, float* dst) { conversion.convert(src, n, dst); },
      progress, settings.threads);
  ToRgbReport rep = conversion.finish(log);
  rep.mip_levels = reader.mip_levels();
  rep.subimages = reader.subimages();
  rep.seconds = seconds_since(t_start);
  if (before_commit) before_commit(rep);
  file.commit();
  return rep;
}

}  // namespace spectralize
