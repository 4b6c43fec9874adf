// Planning a batch (plan_ingest, ingest/ingest.h; docs/DESIGN.md §12) on small libraries written
// here: the outputs mirror the source tree and the walk names everything it leaves out; requests
// that would ingest their own outputs are refused; list files are read relative to the list;
// shards are disjoint parts that cover the batch with one identity; and what the plan promises
// beyond that: glob patterns mirror their matches below their fixed part and name what they
// cannot take, each input is taken once whatever its spellings, two inputs naming one output
// both fail, an output that would replace an input fails that file while a manifest that would
// refuses the batch, data copies go beside their outputs, the batch's identity follows the
// config's content and N (not the config's path), and wrong requests are refused by their
// class (Error, FileError, ConfigError). Oracles: the files each case writes, the documented
// name pattern ("{dir}/{stem}.exr") and manifest names, and the file system.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "ingest/ingest.h"
#include "ingest_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("ingest_plan") {}
};

using test::request_for;
using test::write_png;

// A path relative to `base`, as text ("walls/b.exr").
std::string relative_to(const std::string& path, const fs::path& base) {
  return fs::path(path).lexically_relative(base).generic_string();
}

// The outputs of a plan relative to its destination, by input relative to `source`.
std::map<std::string, std::string> outputs_of(const IngestPlan& plan, const fs::path& source) {
  std::map<std::string, std::string> out;
  for (const IngestItem& i : plan.items)
    out[relative_to(i.input, source)] = relative_to(i.output, plan.request.destination);
  return out;
}

// The kind of what the walk left out, by path relative to `source` ("" when not left out).
std::string left_out_kind(const IngestPlan& plan, const fs::path& source, const std::string& rel,
                          bool* failure = nullptr) {
  for (const LeftOut& l : plan.left_out)
    if (relative_to(l.path, source) == rel) {
      if (failure) *failure = l.failure;
      return l.kind;
    }
  return "";
}

// --- Planning ---

TEST(IngestPlan, TheOutputsMirrorTheTreeAndTheWalkNamesWhatItLeavesOut) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a_basecolor.png");
  write_png(lib / "walls/b_basecolor.png");
  write_png(lib / "walls/deep/c.png");
  std::ofstream(lib / "notes.txt") << "not an image";
  write_png(lib / ".hidden.png");
  std::ofstream(lib / "walls/.c.exr.spectralize-AbC123.tmp") << "a killed run's";
  fs::create_symlink(lib / "nowhere.png", lib / "dangling.png");
  fs::create_symlink(lib, lib / "walls/loop");             // back to an ancestor
  fs::create_symlink(lib / "walls", lib / "z_walls_too");  // a folder walked before
  // The library, and one of its files again by another spelling.
  const IngestPlan plan = plan_ingest(request_for(
      {lib.string(), (lib / "walls/../a_basecolor.png").string()}, (t.dir / "out").string()));
  EXPECT_EQ(outputs_of(plan, lib),
            (std::map<std::string, std::string>{{"a_basecolor.png", "a_basecolor.exr"},
                                                {"walls/b_basecolor.png", "walls/b_basecolor.exr"},
                                                {"walls/deep/c.png", "walls/deep/c.exr"}}));
  for (const IngestItem& i : plan.items) {
    EXPECT_EQ(i.relative, relative_to(i.output, t.dir / "out"));
    EXPECT_EQ(i.source_relative, relative_to(i.input, lib));
    EXPECT_TRUE(i.failure.empty()) << i.failure;
  }
  EXPECT_EQ(plan.all_items, 3u);
  EXPECT_EQ(plan.manifest, (t.dir / "out/spectralize-ingest.jsonl").string());
  bool failure = true;
  EXPECT_EQ(left_out_kind(plan, lib, "notes.txt", &failure), "not_image");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, ".hidden.png"), "hidden");
  EXPECT_EQ(left_out_kind(plan, lib, "walls/.c.exr.spectralize-AbC123.tmp"), "temporary");
  EXPECT_EQ(left_out_kind(plan, lib, "dangling.png", &failure), "dangling_link");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "z_walls_too", &failure), "same_folder");
  EXPECT_FALSE(failure);
  // A loop is a failure of the walk (the batch exits 1): it could not do its job there.
  EXPECT_EQ(left_out_kind(plan, lib, "walls/loop", &failure), "loop");
  EXPECT_TRUE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "walls/../a_basecolor.png"), "duplicate");
}

TEST(IngestPlan, RequestsThatWouldIngestTheirOwnOutputsAreRefused) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "walls/a.png");
  // The destination inside a source folder, or where a pattern looks: a command-line mistake
  // (Error, exit 2), never a FileError.
  auto refused = [](const IngestRequest& r, std::vector<std::string> words) {
    try {
      plan_ingest(r);
      ADD_FAILURE() << "accepted";
    } catch (const FileError& e) {
      ADD_FAILURE() << "a FileError: " << e.what();
    } catch (const Error& e) {
      for (const std::string& w : words)
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what() << " lacks " << w;
    }
  };
  refused(request_for({lib.string()}, (lib / "out").string()),
          {"'" + (lib / "out").string() + "'", "inside the source folder"});
  refused(request_for({(lib / "*/*.png").string()}, (lib / "spectral").string()),
          {"'" + (lib / "spectral").string() + "'", "looks for files"});
  IngestRequest shard = request_for({lib.string()}, (t.dir / "out").string());
  shard.shard = 2;
  shard.shards = 2;
  refused(shard, {"shard 2/2"});
  fs::create_directories(t.dir / "empty");
  refused(request_for({(t.dir / "empty").string()}, (t.dir / "out").string()),
          {"no input files found"});
  // A destination that is a file: the file system's refusal (FileError, exit 1).
  std::ofstream(t.dir / "blocker") << "a file";
  test::expect_error_mentioning(
      [&] { plan_ingest(request_for({lib.string()}, (t.dir / "blocker").string())); },
      {"blocker", "is not a folder"}, "a file as the destination");
  EXPECT_FALSE(fs::exists(lib / "out"));
  EXPECT_FALSE(fs::exists(lib / "spectral"));
}

TEST(IngestPlan, ListLinesAreRelativeToTheListAndMayCarryTheirOwnSettings) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  write_png(lib / "sky/b.png");
  std::ofstream(lib / "list.txt")
      << "# two files\n\na.png\n"
         "{\"input\": \"sky/b.png\", \"wavelengths\": \"400:700:10\"}\n";
  IngestRequest r = request_for({}, (t.dir / "out").string());
  r.inputs_from = (lib / "list.txt").string();
  const IngestPlan plan = plan_ingest(r);
  ASSERT_EQ(plan.items.size(), 2u);
  EXPECT_EQ(outputs_of(plan, lib),
            (std::map<std::string, std::string>{{"a.png", "a.exr"}, {"sky/b.png", "sky/b.exr"}}));
  for (const IngestItem& i : plan.items) {
    const bool b = i.input.find("b.png") != std::string::npos;
    EXPECT_EQ(i.settings.spectral.grid.size(), b ? 31u : 81u)
        << i.input;  // 400:700:10, or 380:780:5
  }
  // A malformed line is named.
  std::ofstream(lib / "bad.txt") << "a.png\n{\"input\": 3}\n";
  r.inputs_from = (lib / "bad.txt").string();
  test::expect_error_mentioning([&] { plan_ingest(r); }, {"bad.txt", "line 2"}, "a bad line");
}

TEST(IngestPlan, AListLineMayNameItsSourceFolderAndItsOrigin) {
  TempDir t;
  const fs::path stage = t.dir / "stage";
  write_png(stage / "tex/a.png");
  write_png(stage / "tex/b.png");
  const fs::path lists = t.dir / "lists";
  fs::create_directories(lists);
  // "source": the input is relative to it, and the output mirrors its place there; "origin"
  // is kept as given, its reasons become those of the settings the line gives.
  std::ofstream(lists / "list.txt")
      << "{\"input\": \"tex/a.png\", \"source\": \"" << stage.string()
      << "\", \"colorspace\": \"data\", \"origin\": {\"where\": \"</M/A>.inputs:file\", "
         "\"colorspace_reason\": \"the stage says raw\", \"mode_reason\": \"unused\"}}\n"
         "{\"input\": \"../stage/tex/b.png\", \"mode\": \"emission\"}\n";
  IngestRequest r = request_for({}, (t.dir / "out").string());
  r.inputs_from = (lists / "list.txt").string();
  const IngestPlan plan = plan_ingest(r);
  ASSERT_EQ(plan.items.size(), 2u);
  const IngestItem& a =
      plan.items[0].input.find("a.png") != std::string::npos ? plan.items[0] : plan.items[1];
  const IngestItem& b = &a == &plan.items[0] ? plan.items[1] : plan.items[0];
  EXPECT_EQ(a.input, (stage / "tex/a.png").string());
  EXPECT_EQ(a.relative, "tex/a.exr");
  EXPECT_EQ(nlohmann::json::parse(a.origin)["where"], "</M/A>.inputs:file");
  EXPECT_EQ(a.settings.colorspace_given_by, "the stage says raw");
  EXPECT_EQ(a.settings.mode_given_by, "");  // the line gives no mode
  EXPECT_TRUE(a.settings.stated_for_file);
  // Relative to the list, leaving it: no folder to mirror.
  EXPECT_EQ(b.relative, "b.exr");
  EXPECT_TRUE(b.settings.stated_for_file);
  EXPECT_EQ(b.origin, "");
  // A malformed origin or source is named with its line.
  for (const char* bad :
       {R"({"input": "a.png", "origin": "here"})", R"({"input": "a.png", "source": 3})",
        R"({"input": "a.png", "origin": {"where": 3}})"}) {
    std::ofstream(lists / "bad.txt") << bad << "\n";
    r.inputs_from = (lists / "bad.txt").string();
    test::expect_error_mentioning([&] { plan_ingest(r); }, {"bad.txt", "line 1"}, bad);
  }
}

TEST(IngestPlan, AListLineMayNameWhatItsOutputMirrorsOrBeAKnownFailure) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "tex/a.png");
  write_png(lib / "tex/b.png");
  // The same file twice, with two decisions, each under its own name; a known failure; and
  // the folder walked too: the listed files are taken with their lines, the walk's left out.
  std::ofstream(lib / "list.txt")
      << R"({"input": "tex/a.png", "mode": "reflectance", "as": "tex/a.reflectance.png"})"
      << "\n"
      << R"({"input": "tex/a.png", "mode": "emission", "as": "tex/a.emission.png"})"
      << "\n"
      << R"({"input": "stage.usda", "failure": "a light with a negative colour"})"
      << "\n";
  IngestRequest r = request_for({lib.string()}, (t.dir / "out").string());
  r.inputs_from = (lib / "list.txt").string();
  const IngestPlan plan = plan_ingest(r);
  std::map<std::string, std::string> by_output;
  for (const IngestItem& i : plan.items)
    by_output[i.relative] = i.failure.empty() ? i.input : "failed: " + i.failure;
  EXPECT_EQ(by_output["tex/a.reflectance.exr"], (lib / "tex/a.png").string());
  EXPECT_EQ(by_output["tex/a.emission.exr"], (lib / "tex/a.png").string());
  EXPECT_EQ(by_output["tex/b.exr"], (lib / "tex/b.png").string());  // walked: its own
  EXPECT_EQ(by_output["stage.exr"], "failed: a light with a negative colour");
  EXPECT_EQ(by_output.size(), 4u);
  std::size_t duplicates = 0;
  for (const LeftOut& l : plan.left_out)
    if (l.kind == "duplicate" && l.reason.find("a list line gives") != std::string::npos)
      ++duplicates;
  EXPECT_EQ(duplicates, 1u);  // tex/a.png, found by the walk
  for (const char* bad :
       {R"({"input": "a.png", "as": "../x.png"})", R"({"input": "a.png", "as": "/abs.png"})",
        R"({"input": "a.png", "failure": ""})"}) {
    std::ofstream(lib / "bad.txt") << bad << "\n";
    r.inputs_from = (lib / "bad.txt").string();
    test::expect_error_mentioning([&] { plan_ingest(r); }, {"bad.txt", "line 1"}, bad);
  }
}

// --- Shards ---

TEST(IngestPlan, ShardsAreDisjointPartsThatCoverTheBatchStableAsFilesComeAndGo) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  for (int i = 0; i < 12; ++i)
    write_png(lib / (i % 2 ? "walls" : "floors") / ("tile" + std::to_string(i) + ".png"));
  const std::string out = (t.dir / "out").string();
  auto plan_of = [&](int shard, int shards) {
    IngestRequest r = request_for({lib.string()}, out);
    r.shard = shard;
    r.shards = shards;
    return plan_ingest(r);
  };
  auto split = [&](int shards) {
    std::vector<std::set<std::string>> parts;
    std::set<std::string> batches;
    for (int k = 0; k < shards; ++k) {
      const IngestPlan p = plan_of(k, shards);
      std::set<std::string> part;
      for (const IngestItem& i : p.items) part.insert(i.relative);
      parts.push_back(part);
      batches.insert(p.batch);
      EXPECT_EQ(p.manifest, out + "/spectralize-ingest.part-" + std::to_string(k) + "-of-" +
                                std::to_string(shards) + ".jsonl");
    }
    EXPECT_EQ(batches.size(), 1u) << "the shards of one batch disagree on its identity";
    return std::pair{parts, *batches.begin()};
  };
  std::set<std::string> all;
  for (const IngestItem& i : plan_of(0, 1).items) all.insert(i.relative);
  ASSERT_EQ(all.size(), 12u);
  const auto [parts, batch] = split(3);
  std::set<std::string> together;
  std::size_t sizes = 0;
  for (const auto& part : parts) {
    EXPECT_LT(part.size(), 12u);  // a split, not everything in one
    sizes += part.size();
    together.insert(part.begin(), part.end());
  }
  EXPECT_EQ(sizes, 12u);  // disjoint
  EXPECT_EQ(together, all);
  // A new file takes its place; every other file stays in its shard. The batch is another.
  write_png(lib / "walls/tile12.png");
  const auto [grown, grown_batch] = split(3);
  for (int k = 0; k < 3; ++k) {
    std::set<std::string> without = grown[k];
    without.erase("walls/tile12.exr");
    EXPECT_EQ(without, parts[k]) << "shard " << k;
  }
  EXPECT_NE(grown_batch, batch);
}

TEST(IngestPlan, TheBatchIdentityFollowsWhatShapesTheFilesNotHowTheBatchRuns) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  write_png(lib / "b.png");
  const IngestRequest base = request_for({lib.string()}, (t.dir / "out").string());
  const std::string batch = plan_ingest(base).batch;
  IngestRequest faster = base;
  faster.settings.threads = 1;
  faster.settings.ingest.jobs = 3;
  EXPECT_EQ(plan_ingest(faster).batch, batch);
  IngestRequest other = base;
  other.settings.spectral.grid = WavelengthGrid(400, 700, 10);
  EXPECT_NE(plan_ingest(other).batch, batch);
}

// --- What else the plan promises ---

// A file's planned item by its input's file name (nullptr when not planned).
const IngestItem* item_named(const IngestPlan& plan, const std::string& name) {
  for (const IngestItem& i : plan.items)
    if (fs::path(i.input).filename() == name) return &i;
  return nullptr;
}

// A 4 x 4 RGB image in the format of `path`'s extension.
void write_image(const fs::path& path) {
  fs::create_directories(path.parent_path());
  const OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeUInt8);
  std::vector<unsigned char> px(4 * 4 * 3, 90);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out && out->open(path.string(), spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
  ASSERT_TRUE(out->close());
}

TEST(IngestPlan, APatternMirrorsItsMatchesBelowItsFixedPartAndNamesWhatItCannotTake) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "walls/a.png");
  write_png(lib / "floors/b.png");
  fs::create_directories(lib / "floors/deep.png");  // a folder the pattern matches
  std::ofstream(lib / "walls/notes.txt") << "not an image";
  const std::string pattern = (lib / "*/*").string();
  const std::string nothing = (lib / "*/*.tif").string();
  const IngestPlan plan = plan_ingest(request_for({pattern, nothing}, (t.dir / "out").string()));
  std::map<std::string, std::string> outputs;
  for (const IngestItem& i : plan.items)
    if (i.failure.empty()) outputs[relative_to(i.input, lib)] = i.relative;
  // Below "lib", the pattern's part without wildcards.
  EXPECT_EQ(outputs, (std::map<std::string, std::string>{{"floors/b.png", "floors/b.exr"},
                                                         {"walls/a.png", "walls/a.exr"}}));
  bool failure = true;
  EXPECT_EQ(left_out_kind(plan, lib, "floors/deep.png", &failure), "folder_match");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "walls/notes.txt"), "not_image");
  // A pattern that matches nothing is a failure of its own, named, not a silent nothing.
  std::size_t failed = 0;
  for (const IngestItem& i : plan.items)
    if (!i.failure.empty()) {
      ++failed;
      EXPECT_NE(i.failure.find(nothing), std::string::npos) << i.failure;
      EXPECT_NE(i.failure.find("matches no image file"), std::string::npos) << i.failure;
    }
  EXPECT_EQ(failed, 1u);
}

TEST(IngestPlan, EachInputIsTakenOnceWhateverItsSpellings) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  write_png(lib / "b.png");
  fs::create_symlink(lib / "a.png", t.dir / "link_to_a.png");
  // The folder twice (another spelling), and one of its files again by a link.
  const IngestPlan plan = plan_ingest(
      request_for({lib.string(), (lib / ".").string() + "/", (t.dir / "link_to_a.png").string()},
                  (t.dir / "out").string()));
  EXPECT_EQ(plan.items.size(), 2u);
  EXPECT_EQ(plan.all_items, 2u);
  std::map<std::string, int> kinds;
  for (const LeftOut& l : plan.left_out) {
    ++kinds[l.kind];
    EXPECT_FALSE(l.failure) << l.path;
  }
  EXPECT_EQ(kinds, (std::map<std::string, int>{{"duplicate", 1}, {"same_folder", 1}}));
}

TEST(IngestPlan, TwoInputsNamingOneOutputBothFailNamingBoth) {
  TempDir t;
  // One relative path under two sources: both would be walls/a.exr.
  write_png(t.dir / "lib1/walls/a.png");
  write_png(t.dir / "lib2/walls/a.png");
  write_png(t.dir / "lib2/walls/c.png");
  const IngestPlan plan = plan_ingest(request_for(
      {(t.dir / "lib1").string(), (t.dir / "lib2").string()}, (t.dir / "out").string()));
  ASSERT_EQ(plan.items.size(), 3u);
  for (const IngestItem& i : plan.items) {
    SCOPED_TRACE(i.input);
    if (fs::path(i.input).filename() == "c.png") {
      EXPECT_EQ(i.failure, "");
      continue;
    }
    for (const char* source : {"lib1/walls/a.png", "lib2/walls/a.png"})
      EXPECT_NE(i.failure.find(source), std::string::npos) << i.failure;
    EXPECT_NE(i.failure.find("--name-pattern"), std::string::npos) << i.failure;
  }
}

TEST(IngestPlan, SameStemSiblingsEachKeepAnOutputOfTheirOwn) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_image(lib / "a.png");
  write_image(lib / "a.tif");
  const IngestPlan plan = plan_ingest(request_for({lib.string()}, (t.dir / "out").string()));
  ASSERT_EQ(plan.items.size(), 2u);
  const IngestItem* png = item_named(plan, "a.png");
  const IngestItem* tif = item_named(plan, "a.tif");
  ASSERT_TRUE(png && tif);
  EXPECT_EQ(png->failure, "");
  EXPECT_EQ(tif->failure, "");
  EXPECT_NE(png->output, tif->output);  // never one file written twice
  // Each named with its extension before .exr (docs/DESIGN.md §12).
  EXPECT_NE(png->relative.find("png"), std::string::npos) << png->relative;
  EXPECT_NE(tif->relative.find("tif"), std::string::npos) << tif->relative;
  for (const IngestItem* i : {png, tif}) {
    EXPECT_EQ(fs::path(i->relative).extension(), ".exr") << i->relative;
    EXPECT_EQ(i->output, (t.dir / "out" / i->relative).string());
  }
}

TEST(IngestPlan, AnOutputThatWouldReplaceAnInputFailsThatFileAloneAndOneOutsideFailsToo) {
  TempDir t;
  const fs::path out = t.dir / "out";
  // An OpenEXR input in the destination, given by name: its output, out/a.exr, is itself.
  write_image(out / "a.exr");
  write_png(t.dir / "b.png");
  const IngestPlan plan = plan_ingest(
      request_for({(out / "a.exr").string(), (t.dir / "b.png").string()}, out.string()));
  const IngestItem* a = item_named(plan, "a.exr");
  const IngestItem* b = item_named(plan, "b.png");
  ASSERT_TRUE(a && b);
  EXPECT_NE(a->failure, "");
  EXPECT_NE(a->failure.find("a.exr"), std::string::npos) << a->failure;
  EXPECT_EQ(b->failure, "");
  // A name pattern that leads out of the destination: that file's failure.
  IngestRequest up = request_for({(t.dir / "b.png").string()}, out.string());
  apply_setting(up.settings, *find_setting("name_pattern"), "../{stem}.exr", "--name-pattern");
  const IngestPlan away = plan_ingest(up);
  ASSERT_EQ(away.items.size(), 1u);
  EXPECT_NE(away.items[0].failure.find("leaves the destination"), std::string::npos)
      << away.items[0].failure;
}

TEST(IngestPlan, AManifestThatWouldReplaceAnInputRefusesTheBatch) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  IngestRequest r = request_for({lib.string()}, (t.dir / "out").string());
  r.manifest = (lib / "a.png").string();
  test::expect_error_mentioning([&] { plan_ingest(r); }, {"--manifest", "a.png"},
                                "the manifest over an input");
  try {
    plan_ingest(r);
  } catch (const FileError&) {
  } catch (const Error& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
  }
  // A manifest elsewhere is where it was asked to be.
  r.manifest = (t.dir / "elsewhere.jsonl").string();
  EXPECT_EQ(plan_ingest(r).manifest, r.manifest);
}

TEST(IngestPlan, DataCopiesGoBesideTheirOutputsOnlyWhenAsked) {
  TempDir t;
  const fs::path lib = t.dir / "lib", out = t.dir / "out";
  write_png(lib / "walls/b_normal.png");
  IngestRequest r = request_for({lib.string()}, out.string());
  EXPECT_EQ(plan_ingest(r).items.at(0).copy, "");
  r.settings.ingest.copy_data = true;
  const IngestPlan plan = plan_ingest(r);
  ASSERT_EQ(plan.items.size(), 1u);
  EXPECT_EQ(plan.items[0].copy, (out / "walls/b_normal.png").string());
  EXPECT_EQ(plan.items[0].copy_failure, "");
}

TEST(IngestPlan, WhatTheWalkMeetsOfTheDestinationAndOfOtherFilesIsLeftOutByKind) {
  TempDir t;
  const fs::path lib = t.dir / "lib", out = t.dir / "out";
  write_png(lib / "a.png");
  fs::create_directories(out);
  fs::create_symlink(out, lib / "to_out");  // the destination, reached from the source
  ASSERT_EQ(::mkfifo((lib / "pipe.png").c_str(), 0600), 0);
  const IngestPlan plan = plan_ingest(request_for({lib.string()}, out.string()));
  EXPECT_EQ(plan.items.size(), 1u);
  bool failure = true;
  EXPECT_EQ(left_out_kind(plan, lib, "to_out", &failure), "destination");
  EXPECT_FALSE(failure);
  EXPECT_EQ(left_out_kind(plan, lib, "pipe.png", &failure), "not_regular");
  EXPECT_FALSE(failure);
  // A missing file given by name is planned: it fails when run, the others carry on.
  const IngestPlan missing = plan_ingest(
      request_for({(t.dir / "missing.png").string(), (lib / "a.png").string()}, out.string()));
  EXPECT_EQ(missing.items.size(), 2u);
  ASSERT_NE(item_named(missing, "missing.png"), nullptr);
  EXPECT_EQ(item_named(missing, "missing.png")->relative, "missing.exr");
}

TEST(IngestPlan, TheBatchIdentityFollowsTheConfigsContentAndTheShardCount) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  const std::string shipped =
      std::string(SPECTRALIZE_SOURCE_DIR) + "/ocio_configs/spectralize.ocio";
  std::ifstream in(shipped);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::ofstream(t.dir / "one.ocio") << text;
  std::ofstream(t.dir / "same.ocio") << text;                            // same bytes, elsewhere
  std::ofstream(t.dir / "other.ocio") << text << "\n# one more line\n";  // other bytes
  auto plan_with = [&](const std::string& config, int shards = 1) {
    IngestRequest r = request_for({lib.string()}, (t.dir / "out").string());
    r.settings.config = (t.dir / config).string();
    r.shards = shards;
    return plan_ingest(r);
  };
  const IngestPlan one = plan_with("one.ocio"), same = plan_with("same.ocio"),
                   other = plan_with("other.ocio");
  EXPECT_FALSE(one.config_identity.empty());
  EXPECT_EQ(same.config_identity, one.config_identity);
  EXPECT_EQ(same.batch, one.batch);  // by content, not by path
  EXPECT_NE(other.config_identity, one.config_identity);
  EXPECT_NE(other.batch, one.batch);
  EXPECT_EQ(plan_with("one.ocio").batch, one.batch);  // the same request, the same batch
  EXPECT_NE(plan_with("one.ocio", 2).batch, one.batch);
}

TEST(IngestPlan, WrongRequestsAreRefusedByTheirClass) {
  TempDir t;
  const fs::path lib = t.dir / "lib";
  write_png(lib / "a.png");
  const std::string out = (t.dir / "out").string();
  // Command-line mistakes: Error, never FileError.
  auto command_line = [](IngestRequest r, std::vector<std::string> words, const std::string& what) {
    try {
      plan_ingest(r);
      ADD_FAILURE() << what << ": accepted";
    } catch (const FileError& e) {
      ADD_FAILURE() << what << ": a FileError: " << e.what();
    } catch (const Error& e) {
      for (const std::string& w : words)
        EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what() << " lacks " << w;
    }
  };
  command_line(request_for({lib.string()}, ""), {"-o DESTDIR"}, "no destination");
  for (const auto& [shard, shards] : {std::pair{-1, 2}, {0, 0}, {3, 2}}) {
    IngestRequest r = request_for({lib.string()}, out);
    r.shard = shard;
    r.shards = shards;
    command_line(r, {std::to_string(shard) + "/" + std::to_string(shards)}, "a bad shard");
  }
  std::ofstream(lib / "unknown.txt") << "a.png\n{\"input\": \"a.png\", \"colour\": \"red\"}\n";
  std::ofstream(lib / "batch_key.txt") << "{\"input\": \"a.png\", \"jobs\": \"2\"}\n";
  for (const auto& [list, word] : {std::pair<std::string, std::string>{"unknown.txt", "line 2"},
                                   {"batch_key.txt", "line 1"}}) {
    IngestRequest r = request_for({}, out);
    r.inputs_from = (lib / list).string();
    command_line(r, {list, word, "unknown key"}, list);
  }
  // A list that cannot be read: the file system's refusal.
  IngestRequest missing_list = request_for({}, out);
  missing_list.inputs_from = (t.dir / "no_list.txt").string();
  try {
    plan_ingest(missing_list);
    ADD_FAILURE() << "a missing list accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("no_list.txt"), std::string::npos) << e.what();
  }
  // A config that does not load: ConfigError.
  std::ofstream(t.dir / "bad.ocio") << "ocio_profile_version: 2\nroles: [\n";
  IngestRequest bad_config = request_for({lib.string()}, out);
  bad_config.settings.config = (t.dir / "bad.ocio").string();
  EXPECT_THROW(plan_ingest(bad_config), ConfigError);
  EXPECT_FALSE(fs::exists(out));  // nothing of a refused plan is written
}

}  // namespace
}  // namespace spectralize
