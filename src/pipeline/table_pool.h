#pragma once
// Spectralizers and their node tables shared by every file of a batch (docs/DESIGN.md §4): one
// table per combination of the settings the spectra depend on and the --cache folder, loaded
// once from that folder and saved once at the end, merged with what other processes saved
// meanwhile.

#include <cstdint>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "core/tables/spectral_table.h"
#include "pipeline/job_log.h"
#include "settings/settings.h"
#include "spectralize/core/spectralizer.h"

namespace spectralize {

class TablePool {
 public:
  /// The shared spectralizer and table for these settings (mode resolved) in the RGB frame of
  /// the input's colour space (pipeline/render_table.h table_frame), with its cache file and
  /// status; built (and loaded from settings.cache_dir) on first use. Messages name the folder's
  /// option as `cache_option` ("--cache" on the command line, "cache" in Python). Thread-safe:
  /// callers asking for an entry being built wait for it (one spectralizer per kind).
  /// Cost: a spectralizer (~10-60 ms) plus loading the cache file the first time, O(log
  /// tables) after.
  struct Entry {
    std::unique_ptr<Spectralizer> spectralizer;
    std::unique_ptr<SpectralTable> table;
    std::string key, file_key, cache_file, cache_status;
    std::uint64_t saved_computed = 0;  // nodes_computed at the last save
  };
  Entry& get(const Settings& settings, const Mat3& frame, const LogFn& log,
             const std::string& cache_option = "--cache");

  /// Saves every table that grew since it was loaded or last saved to its cache file (merged
  /// with the file's current nodes, so concurrent batches on one folder add up). Returns the
  /// warnings. Cost: O(nodes) per table saved.
  std::vector<std::string> save();

 private:
  Entry& build(const Settings& settings, const Mat3& frame, const LogFn& log,
               const std::string& cache_option, const std::string& seen);

  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Entry>> entries_;
  // The entry of settings already seen, by what the key is made from (no spectralizer built to
  // find it again: that is ~1 ms per file).
  std::map<std::string, Entry*> seen_;
  // Entries being built, by the same text: other files of that kind wait for them.
  std::map<std::string, std::shared_future<Entry*>> building_;
};

}  // namespace spectralize
