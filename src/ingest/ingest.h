#pragma once
// `spectralize ingest`: whole texture libraries to spectral OpenEXR (docs/DESIGN.md §12). The
// inputs (files, folders walked recursively, glob patterns, a list file) are planned into
// outputs that mirror their source trees; each file gets a decision with its reason (colour
// space, mode, or non-colour data that is skipped or copied); outputs whose recorded inputs and
// settings still match are skipped; the rest are converted in parallel through one shared node
// table; a JSON Lines manifest records what happened. A batch splits deterministically into
// shards for a farm (Slurm job arrays), whose manifests merge into one.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/work_counts.h"
#include "imagefile/safe_output.h"
#include "pipeline/job_log.h"
#include "pipeline/job_plan.h"
#include "settings/settings.h"

namespace spectralize {

/// What the command line asked for.
struct IngestRequest {
  std::vector<std::string> sources;     // files, folders (walked), glob patterns
  std::string inputs_from;              // a list of inputs: paths, or JSON objects per line
  std::vector<std::string> made_lists;  // lists made for the batch (a USD stage's textures)
  std::string destination;              // the output folder
  std::string manifest;                 // the manifest to write ("" : in the destination)
  bool force = false;                   // convert even what is up to date
  int shard = 0, shards = 1;            // this process does the files of shard `shard` of `shards`
                                        // (checked by ingest/shard.h's parse_shard or slurm_shard)
  Settings settings;                    // every file's settings (a list line may override them)
  OptionNames names{"--", "-o"};        // how the caller spells options in messages (CLI, Python)
};

/// One planned file.
struct IngestItem {
  std::string input, output;    // paths as used
  std::string relative;         // the output relative to the destination (mirrors the source)
  std::string source_relative;  // the input relative to its source (what the output mirrors)
  std::string copy;             // where `--data copy` would copy it ("" : not copied)
  Settings settings;            // the batch's, with a list line's overrides
  std::string failure;          // set at planning (e.g. two inputs for one output)
  std::string copy_failure;     // set at planning: why it cannot be copied, should it be data
  std::string derived_from;     // made from this input of the batch (same_stem.h): not converted
  std::string note;             // how planning named it (same-stem siblings)
  std::string origin;           // a list line's "origin" object, as JSON text ("" : none)
};

/// What the walk left out or could not enter, by name: a hidden file, a non-image, a link to a
/// device, a dangling link, the destination reached again, a file given twice, an unreadable
/// folder, a loop. `failure`: the walk could not do its job there (the batch exits 1).
struct LeftOut {
  std::string path;
  std::string kind;    // a short class for counts: "not_image", "hidden", "unreadable_folder", ...
  std::string reason;  // for people: "not an image (by its extension)"
  bool failure = false;
};

struct IngestPlan {
  IngestRequest request;
  std::vector<IngestItem> items;  // this shard's files, in order
  std::size_t all_items = 0;      // the whole batch (every shard)
  std::vector<LeftOut> left_out;  // of the whole batch, in walk order
  std::string manifest;           // where the manifest goes
  std::string batch;              // the batch's identity (every shard's plan agrees)
  std::string config_identity;    // the OCIO config by content (ColourSpaces::content_identity)
  FilePlan files;                 // everything the batch reads and writes, checked
  JobPlan job;                    // the request's settings planned: the config, parsed once
};

/// Walks, expands and reads the inputs (each file once, whatever its spellings), names the
/// outputs, plans every file the batch writes against every file it reads and against each other
/// (a conflict is that file's failure; a manifest in conflict refuses the batch) and keeps this
/// shard's files. Throws Error (a wrong command line: exit 2) for a destination inside a source
/// folder (also by a glob pattern that reaches into it), a malformed list (naming the line), a
/// bad shard or no inputs at all; FileError (exit 1) for a destination or manifest that cannot
/// be written, an unreadable list; ConfigError for a config that does not load. Cost: a
/// directory walk and a few stats per file.
IngestPlan plan_ingest(const IngestRequest& request);
/// As above with the job already planned for request.settings (a front end that checked its
/// options by planning: the batch is planned once). Cost: as above.
IngestPlan plan_ingest(const IngestRequest& request, std::optional<JobPlan> job);

/// Counts of a batch, for the summary and the manifest's last record.
struct IngestSummary {
  std::uint64_t converted = 0, up_to_date = 0, skipped_data = 0, copied_data = 0, derived = 0,
                failed = 0;
  std::uint64_t pixels = 0, stale_temporaries_removed = 0;
  std::uint64_t left_out = 0, not_entered = 0;  // left out of the walk; of them, failures
  std::map<std::string, std::uint64_t> left_out_by_reason;  // "not an image": 3, ...
  double seconds = 0;
  // What converting the files took beyond their pixels (the planning before is not counted): a
  // config parsed, spectralizers built, OCIO file-rule matches, inputs opened (each once).
  WorkCounts work;
  std::string manifest;
  /// True when nothing failed: no file, and the walk entered everything. Cost: O(1).
  bool ok() const { return failed == 0 && not_entered == 0; }
  bool interrupted = false;           // stopped on request: the files below were not done
  std::uint64_t not_done = 0;         // files of the plan left undone by the interruption
  std::vector<std::string> failures;  // each failed file's manifest record (JSON), in order
  /// Files handled, all statuses. Cost: O(1).
  std::uint64_t files() const {
    return converted + up_to_date + skipped_data + copied_data + derived + failed;
  }
};

/// The counts as one JSON object (files, converted, ..., seconds, manifest): the manifest's
/// summary record. Cost: O(1).
std::string ingest_summary_json(const IngestSummary& summary);

/// Progress across files: done of total, and one-line news of the file just finished.
using IngestProgressFn =
    std::function<void(std::uint64_t done, std::uint64_t total, const std::string& news)>;

/// Runs the plan: up-to-date checks, decisions, conversions in parallel (settings.ingest.jobs)
/// through one shared node table, the manifest (JSON Lines: a record per file, then a summary).
/// One bad file never stops the others. `stop` (may be null) is polled between files and
/// between strips of a conversion: once true, no file is started, running conversions are
/// abandoned (their temporaries removed), and the manifest records what was done, its summary
/// marked interrupted. Throws Error only when the manifest cannot be written. Cost: the
/// conversions.
IngestSummary run_ingest(const IngestPlan& plan, const IngestProgressFn& progress, const LogFn& log,
                         const std::atomic<bool>* stop = nullptr);

/// Merges the shard manifests of `destination` (written by `--shard I/N` runs) into its
/// manifest, "spectralize-ingest.jsonl", and returns the summary of all of them. The parts must
/// be one batch's (the same batch identity and N), each shard exactly once and complete (its
/// summary last, its records as many as it says), together every file of the batch once.
/// Throws FileError naming missing, foreign, stale, malformed or incomplete parts. Cost:
/// O(records).
IngestSummary merge_ingest_manifests(const std::string& destination);

}  // namespace spectralize
