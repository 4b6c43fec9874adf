// spectralize ingest SRC... -o DESTDIR: a texture library to spectral OpenEXR, with its
// progress, summary and manifest; --merge joins the manifests of a farm's shards.

#include <fmt/core.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <string>
#include <tuple>

#include "core/error.h"
#include "io/ingest.h"
#include "io/job_settings.h"
#include "io/safe_output.h"
#include "tool/flags.h"
#include "tool/options.h"

namespace spectralize::tool {

namespace {

// "I/N" with 0 <= I < N; UsageError naming the value.
std::pair<int, int> parse_shard(const std::string& text, const char* where) {
  const auto slash = text.find('/');
  int i = -1, n = 0;
  auto whole = [](std::string_view t, int& v) {
    auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size();
  };
  if (slash == std::string::npos || !whole(std::string_view(text).substr(0, slash), i) ||
      !whole(std::string_view(text).substr(slash + 1), n) || n < 1 || i < 0 || i >= n)
    throw UsageError{
        fmt::format("{} '{}': expected I/N with 0 <= I < N (shard I of N)", where, clip(text))};
  return {i, n};
}

// The shard of a Slurm array task: (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) of
// SLURM_ARRAY_TASK_COUNT, when they are set.
std::pair<int, int> slurm_shard() {
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  if (!id || !count) return {0, 1};
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  const int first = min ? std::atoi(min) : 0;
  return parse_shard(std::to_string(std::atoi(id) - first) + "/" + count,
                     "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT");
}

void print_summary(const IngestSummary& s, bool merged) {
  const double mpx = static_cast<double>(s.pixels) / 1e6;
  fmt::print(stderr,
             "spectralize ingest: {} files{}: {} converted, {} up to date, {} data skipped, {} "
             "data copied, {} derived from another, {} failed; {:.1f} Mpixel in {:.1f} s ({:.2f} "
             "Mpixel/s, {:.1f} files/s); manifest '{}'\n",
             s.files(), merged ? " (all shards)" : "", s.converted, s.up_to_date, s.skipped_data,
             s.copied_data, s.derived, s.failed, mpx, s.seconds,
             s.seconds > 0 ? mpx / s.seconds : 0.0,
             s.seconds > 0 ? static_cast<double>(s.files()) / s.seconds : 0.0, s.manifest);
}

}  // namespace

int run_ingest_command(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"ingest: -o DESTDIR is required"};
  if (opt.merge) {
    if (!opt.inputs.empty() || !opt.inputs_from.empty())
      throw UsageError{"ingest --merge takes only -o DESTDIR"};
    const IngestSummary s = merge_ingest_manifests(opt.output);
    if (opt.verbosity > 0) print_summary(s, true);
    return s.failed == 0 ? kExitOk : kExitFailure;
  }
  IngestRequest request;
  request.sources = opt.inputs;
  request.inputs_from = opt.inputs_from;
  request.destination = opt.output;
  request.manifest = opt.manifest;
  request.force = opt.force;
  request.settings = opt.settings;
  if (request.sources.empty() && request.inputs_from.empty())
    throw UsageError{"ingest: give the files, folders or patterns to ingest (or --inputs-from)"};
  // The config and colour space are command-line values: checked before any work.
  try {
    request.settings = checked_ingest_settings(request.settings, OptionNames{"--", "-o"});
  } catch (const Error& e) {
    throw UsageError{e.what()};
  }
  std::tie(request.shard, request.shards) =
      opt.shard.empty() ? slurm_shard() : parse_shard(opt.shard, "--shard");
  IngestPlan plan;
  try {
    plan = plan_ingest(request);
  } catch (const Error& e) {
    throw UsageError{e.what()};
  }
  const LogFn log = console_log(opt.verbosity);
  if (opt.verbosity >= 2)
    log(1, fmt::format("ingest: {} files in this shard ({} of {}), {} in the batch; {} files of "
                       "the folders are not images",
                       plan.items.size(), request.shard, request.shards, plan.all_items,
                       plan.not_images));
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  IngestProgressFn progress = [&](std::uint64_t done, std::uint64_t total,
                                  const std::string& news) {
    // A file that failed is an error on stderr, whatever the verbosity; the batch goes on.
    if (news.rfind("failed: ", 0) == 0)
      fmt::print(stderr, "{}spectralize ERROR: {}\n", tty && opt.verbosity > 0 ? "\n" : "",
                 news.substr(8));
    if (opt.verbosity == 0) return;
    if (tty) {
      const int filled = static_cast<int>(30.0 * done / std::max<std::uint64_t>(1, total));
      fmt::print(stderr, "\r[{:<30}] {}/{} files ", std::string(filled, '#'), done, total);
      if (done == total) fmt::print(stderr, "\n");
    } else if (opt.verbosity >= 2) {
      fmt::print(stderr, "spectralize ingest: {}/{} {}\n", done, total, news);
    }
  };
  const IngestSummary s = run_ingest(plan, progress, log);
  if (opt.verbosity > 0) print_summary(s, false);
  return s.failed == 0 ? kExitOk : kExitFailure;
}

}  // namespace spectralize::tool
