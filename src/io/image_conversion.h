#pragma once
// One RGB image to one spectral image, assembled from the io layer's parts (docs/DESIGN.md §10):
// the input's interpretation, the spectralizer and its table with the persistent cache, the
// output layout and the pixel kernel. Shared by the CLI's streamed job and the OpenImageIO
// plugin, which serves the same rows on demand.

#include <OpenImageIO/imageio.h>

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "io/image_report.h"
#include "io/job_log.h"
#include "io/settings.h"
#include "io/table_pool.h"
#include "io/thread_share.h"

namespace spectralize {

class ImageConversion {
 public:
  /// Interprets an input of `spec` (channels, colour space, mode, each with its reason; file
  /// rules need `input`'s name), builds the spectralizer and table (loading the cache of
  /// settings.cache_dir), the output layout and the kernel. Warnings go to `log` and the report.
  /// Throws Error naming the input. Cost: ~1 ms (gamut facets) plus loading the cache file.
  /// `pool`: share the spectralizer and table of a batch (and its cache) instead of building
  /// them; `attributes`: extra string attributes for the output's header; `share`: a batch's
  /// cores, asked again at every call of convert().
  ImageConversion(const std::string& input, const OIIO::ImageSpec& spec,
                  const std::string& format_name, bool straight_alpha, const Settings& settings,
                  const LogFn& log, TablePool* pool = nullptr,
                  const std::map<std::string, std::string>& attributes = {},
                  const ThreadShare* share = nullptr);
  ~ImageConversion();

  /// The spectral image's spec (size, channels, sample type, attributes). Cost: O(1).
  const OIIO::ImageSpec& output_spec() const;
  /// Converts n input pixels (all input channels, float) to n output pixels (float). Thread-safe.
  /// Cost: O(n x bands).
  void convert(const float* in, std::size_t n, float* out);
  /// The report so far: setup fields, and after finish() the counts. Cost: O(1).
  const ImageReport& report() const { return report_; }
  /// Fills the counts and cache statistics into the report and saves the node cache if it grew
  /// (a failure to save is a warning). Cost: O(nodes) when saving.
  const ImageReport& finish(const LogFn& log);

 private:
  void load_cache(const LogFn& log, const std::function<void(const std::string&)>& warn);

  struct Parts;
  std::unique_ptr<Parts> parts_;
  ImageReport report_;
};

}  // namespace spectralize
