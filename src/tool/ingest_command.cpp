// spectralize ingest SRC... -o DESTDIR: a texture library to spectral OpenEXR, with its
// progress, summary and manifest; --merge joins the manifests of a farm's shards.

#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "imagefile/safe_output.h"
#include "ingest/ingest.h"
#include "ingest/shard.h"
#include "pipeline/job_plan.h"
#include "spectralize/core/error.h"
#include "text/strings.h"
#include "tool/console.h"
#include "tool/options.h"
#include "tool/usd_stage.h"

namespace spectralize::tool {

namespace {

void print_summary(const IngestSummary& s, bool merged) {
  const double mpx = static_cast<double>(s.pixels) / 1e6;
  std::string left;
  for (const auto& [kind, n] : s.left_out_by_reason)
    left += fmt::format("{}{} {}", left.empty() ? "" : ", ", n, kind);
  fmt::print(stderr,
             "spectralize ingest: {} files{}: {} converted, {} up to date, {} data skipped, {} "
             "data copied, {} derived from another, {} failed; {} left out{}{}; {:.1f} Mpixel in "
             "{:.1f} s ({:.2f} Mpixel/s, {:.1f} files/s); manifest '{}'\n",
             s.files(), merged ? " (all shards)" : "", s.converted, s.up_to_date, s.skipped_data,
             s.copied_data, s.derived, s.failed, s.left_out, left.empty() ? "" : " (" + left + ")",
             s.not_entered ? fmt::format(", {} not entered", s.not_entered) : "", mpx, s.seconds,
             s.seconds > 0 ? mpx / s.seconds : 0.0,
             s.seconds > 0 ? static_cast<double>(s.files()) / s.seconds : 0.0, s.manifest);
}

// A helper that could not run: why, for the stage.
std::string helper_failure(int status) {
  if (status == 3)
    return "reading a USD stage needs OpenUSD's Python bindings (pip install usd-core) in '" +
           usd_python() + "' (set SPECTRALIZE_PYTHON to a Python that has them)";
  return "the stage could not be read (exit " + std::to_string(status) + ")";
}

// The options of the batch that shape a light's spectrum too, for the helper (Python's names).
std::string light_options(const Settings& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, value] : describe_settings(s, kIngest))
    if (key == "wavelengths" || key == "observer" || key == "model" || key == "filter" ||
        key == "curvature")
      j[key] = value;
  if (!s.config.empty()) j["config"] = s.config;
  return j.dump();
}

}  // namespace

int run_ingest_command(const Options& opt) {
  if (opt.output.empty()) throw UsageError{"ingest: -o DESTDIR is required"};
  if (opt.merge) {
    if (!opt.inputs.empty() || !opt.inputs_from.empty())
      throw UsageError{"ingest --merge takes only -o DESTDIR"};
    const IngestSummary s = merge_ingest_manifests(opt.output);
    if (opt.verbosity > 0) print_summary(s, true);
    return s.ok() ? kExitOk : kExitFailure;
  }
  IngestRequest request;
  std::string stage;  // a USD stage among the sources: its textures come as a list
  for (const std::string& input : opt.inputs) {
    if (!is_usd_stage(input)) {
      request.sources.push_back(input);
    } else if (stage.empty()) {
      stage = input;
    } else {
      throw UsageError{"ingest: one USD stage per batch (its layer is DESTDIR/spectral.usda): '" +
                       stage + "' and '" + input + "'"};
    }
  }
  request.inputs_from = opt.inputs_from;
  request.destination = opt.output;
  request.manifest = opt.manifest;
  request.force = opt.force;
  request.settings = opt.settings;
  if (request.sources.empty() && request.inputs_from.empty() && stage.empty())
    throw UsageError{
        "ingest: give the files, folders, patterns or USD stage to ingest (or --inputs-from)"};
  // The config and colour space are command-line values: checked before any work.
  const OptionNames names{"--", "-o"};
  JobPlan job = usage_checked("", [&] { return plan_to_spectral(request.settings, "", names); });
  request.settings = job.settings;
  const ShardSpec shard = usage_checked("", [&] {
    if (!opt.shard.empty()) return with_context("--shard", [&] { return parse_shard(opt.shard); });
    return slurm_shard().value_or(ShardSpec{});
  });
  request.shard = shard.index;
  request.shards = shard.count;
  if (!stage.empty() && shard.count > 1)
    throw UsageError{
        "ingest: a USD stage is ingested by one process (its layer names every "
        "texture's output); give it without --shard or a job array"};
  // The stage's textures (and what it cannot give: failure lines), as list lines
  // (tool/usd_stage.h), its lights written; its layer after the batch.
  std::optional<ScratchFile> stage_list;
  UsdStageHelper helper;  // one process reads the stage: its list now, its layer at the end
  bool stage_ok = true;
  if (!stage.empty()) {
    if (!std::filesystem::is_regular_file(stage))
      throw FileError("USD stage '" + stage + "': no such file");
    std::error_code ec;
    const std::filesystem::path stage_folder = std::filesystem::absolute(stage).parent_path();
    if (std::filesystem::equivalent(stage_folder, opt.output, ec))
      throw UsageError{"ingest: -o " + quoted_path(opt.output) +
                       " is the folder of the USD stage " + quoted_path(stage) +
                       ": its outputs would lie among the stage's files; choose another"};
    // The folder the helper writes into (lights, .usdz contents), checked as ingest checks it.
    if (std::filesystem::exists(opt.output, ec) && !std::filesystem::is_directory(opt.output, ec))
      throw FileError("-o " + quoted_path(opt.output) +
                      ": is not a folder (ingest writes a tree of files into a folder)");
    std::filesystem::create_directories(opt.output, ec);
    if (!std::filesystem::is_directory(opt.output))
      throw FileError("-o " + quoted_path(opt.output) + ": cannot create the folder" +
                      (ec ? ": " + ec.message() : std::string()));
    stage_list.emplace(std::filesystem::temp_directory_path().string(), "spectralize-usd-",
                       ".jsonl");
    int status = 0;
    try {
      status = helper.start({stage, opt.output, stage_list->path(), light_options(job.settings),
                             std::to_string(opt.verbosity)});
    } catch (const FileError& e) {  // no Python to start: the stage fails, the rest goes on
      fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(stage, 200), e.what());
      status = 1;
    }
    if (status != 0) {
      if (status != 1)  // 1: the helper said why
        fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(stage, 200),
                   helper_failure(status));
      stage_ok = false;
    } else if (std::filesystem::file_size(stage_list->path(), ec) > 0) {
      request.made_lists.push_back(stage_list->path());
    }
    if (request.sources.empty() && request.inputs_from.empty() && request.made_lists.empty()) {
      if (!stage_ok) return kExitFailure;
      // A stage without textures: its lights and layer only.
      const std::string manifest =
          opt.manifest.empty()
              ? (std::filesystem::path(opt.output) / "spectralize-ingest.jsonl").string()
              : opt.manifest;
      const int done = helper.finish(manifest);
      if (done != 0 && done != 1)
        fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(stage, 200), helper_failure(done));
      return done == 0 ? kExitOk : kExitFailure;
    }
  }
  const IngestPlan plan = usage_checked("", [&] { return plan_ingest(request, std::move(job)); });
  const LogFn log = console_log(opt.verbosity);
  if (opt.verbosity >= 2)
    log(1, fmt::format("ingest: {} files in this shard ({} of {}), {} in the batch; {} left out",
                       plan.items.size(), request.shard, request.shards, plan.all_items,
                       plan.left_out.size()));
  // What the walk left out: a failure to enter is an error, the rest is said at -v.
  for (const LeftOut& l : plan.left_out) {
    if (l.failure)
      fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(l.path, 200), l.reason);
    else
      log(1, fmt::format("left out '{}': {}", clip(l.path, 200), l.reason));
  }
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
  if (!stage.empty() && stage_ok) {
    const int status = helper.finish(plan.manifest);
    if (status != 0 && status != 1)
      fmt::print(stderr, "spectralize ERROR: '{}': {}\n", clip(stage, 200), helper_failure(status));
    stage_ok = status == 0;
  }
  return s.ok() && stage_ok ? kExitOk : kExitFailure;
}

}  // namespace spectralize::tool
