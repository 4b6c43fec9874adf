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
#include <vector>

#include "pipeline/image_report.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"
#include "pipeline/table_pool.h"
#include "pipeline/thread_share.h"
#include "settings/settings.h"

namespace spectralize {

/// More string attributes for an output's header, made from the settings as resolved for the
/// file (e.g. ingest's up-to-date key).
using HeaderAttributes =
    std::function<std::map<std::string, std::string>(const Settings& resolved)>;

/// What a conversion may share with others (a batch's) instead of making its own.
struct ConversionContext {
  TablePool* pool = nullptr;           // spectralizers, tables and the cache
  const ThreadShare* share = nullptr;  // a batch's cores: its share, asked at every convert()
  HeaderAttributes attributes;         // more header attributes (they win over the conversion's)
  // A file job's: the header records the warnings known before the pixels
  // (kWarningsAttribute) and room for the counts (count_attributes, zero until the job fills
  // them in at the end: fixed-size doubles, so nothing moves).
  bool record_in_header = false;
};

/// The header attribute that holds the warnings the conversion knew before its pixels (the
/// input's interpretation), as a JSON array of strings; with the recorded counts
/// (count_attributes) they give the conversion's warnings (recorded_warnings). Cost: O(1).
inline constexpr const char* kWarningsAttribute = "spectralize:warnings";

/// The warnings of the conversion that made a file, from its header's string and double
/// attributes: those recorded before its pixels, then count_warnings of its recorded counts
/// (about `input`, as the conversion words them). Cost: O(attributes).
std::vector<std::string> recorded_warnings(const std::map<std::string, std::string>& strings,
                                           const std::map<std::string, double>& doubles,
                                           const std::string& input, const OptionNames& names);

class ImageConversion {
 public:
  /// Converts the input `plan` decided (planned_input: channels, colour space, mode, each with
  /// its reason, the settings as resolved for the file; its messages spell options as the
  /// plan's caller does) of header `spec`: builds the spectralizer and table (loading the
  /// cache of settings.cache_dir), the output layout and the kernel. Warnings go to `log` and
  /// the report. Throws Error naming the input. Cost: ~1 ms (gamut facets) plus loading the
  /// cache file.
  ImageConversion(const JobPlan& plan, const OIIO::ImageSpec& spec, const std::string& format_name,
                  bool straight_alpha, const LogFn& log, const ConversionContext& context = {});
  ~ImageConversion();

  /// The spectral image's spec (size, channels, sample type, attributes). Cost: O(1).
  const OIIO::ImageSpec& output_spec() const;
  /// Converts n input pixels (all input channels, float) to n output pixels (float). Thread-safe.
  /// Cost: O(n x bands).
  void convert(const float* in, std::size_t n, float* out);
  /// The report so far: setup fields, and after finish() the counts. Cost: O(1).
  const ImageReport& report() const { return report_; }
  /// Fills the counts and cache statistics into the report and saves the node cache if it grew
  /// and `save_cache` (a failure to save is a warning; a reader that was not asked to write
  /// passes false). Cost: O(nodes) when saving.
  const ImageReport& finish(const LogFn& log, bool save_cache = true);

 private:
  void load_cache(const LogFn& log, const std::function<void(const std::string&)>& warn);

  struct Parts;
  std::unique_ptr<Parts> parts_;
  ImageReport report_;
};

}  // namespace spectralize
