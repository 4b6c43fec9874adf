// the guide's "Files and guarantees" (docs/guide/files.md) through the real binary, one test per
// promise: no file of a run replaces another or an input under any alias; an output called up to
// date is the file the same settings would write now; names are bytes; the walk names what it
// leaves out; shard specs and merges are checked; one exit-code policy; a file given twice is one
// input; the per-file overhead of a batch. The oracles are the file system (bytes, identities,
// links), the manifests read as strict JSON, and OIIO reading the outputs.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "exr_support.h"
#include "settings/settings.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";
const std::string kShippedConfig = SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_guarantee") {}
};

// The manifest, every line parsed as strict JSON (invalid UTF-8 is a parse error).
std::vector<Json> manifest(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

// The record whose `key` (a path) ends in `suffix`.
Json record(const std::vector<Json>& m, const std::string& suffix,
            const std::string& key = "input") {
  for (const Json& r : m)
    if (r.contains(key) && r[key].is_string()) {
      const std::string v = r[key];
      if (v.size() >= suffix.size() &&
          v.compare(v.size() - suffix.size(), suffix.size(), suffix) == 0)
        return r;
    }
  return Json();
}

// The inputs of the records with `status`, by file name.
std::set<std::string> with_status(const std::vector<Json>& m, const std::string& status) {
  std::set<std::string> out;
  for (const Json& r : m)
    if (r.value("status", "") == status)
      out.insert(fs::path(r["input"].get<std::string>()).filename().string());
  return out;
}

// An image of any size and sample type, every pixel `rgb` (optionally one pixel NaN).
void write_rgb(const std::string& path, int size, OIIO::TypeDesc type, std::array<float, 3> rgb,
               bool one_nan = false) {
  OIIO::ImageSpec spec(size, size, 3, type);
  std::vector<float> px(static_cast<std::size_t>(size) * size * 3);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = rgb[i % 3];
  if (one_nan) px[0] = NAN;
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  ASSERT_TRUE(out->close());
}

// A small library: a colour texture, a light, a data map.
void make_library(const Scratch& s) {
  fs::create_directories(s / "lib/empty");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/ramp.png");
  fs::copy_file(kImages + "hdri_forest_256x128.exr", s / "lib/forest.exr");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/brick_normal.png");
}

// Mounts `from` on `to` (bind) where this machine allows it; unmounted on destruction.
struct BindMount {
  std::string to;
  bool ok = false;
  BindMount(const std::string& from, const std::string& target) : to(target) {
    fs::create_directories(to);
    ok = ::mount(from.c_str(), to.c_str(), nullptr, MS_BIND, nullptr) == 0;
  }
  ~BindMount() {
    if (ok) ::umount2(to.c_str(), MNT_DETACH);
  }
};

// --- Every written path ---

// Truth: whatever spelling names it (the file, a hard link, a symbolic link, "..", a bind
// mount, the shell's /proc/self/fd descriptor, a link to a file not there yet), no file the
// run writes is an input, the config or another of its outputs: refused with exit 1 before any
// work (no output written), the inputs' bytes unchanged.
TEST(Guarantees, NoWrittenPathIsAnInputOrAnotherOutput) {
  Scratch s;
  make_library(s);
  std::map<std::string, std::string> original;
  for (const char* f : {"lib/ramp.png", "lib/forest.exr", "lib/brick_normal.png"})
    original[f] = e2e::slurp(s / f);
  fs::create_hard_link(s / "lib/ramp.png", s / "hard.png");
  fs::create_symlink(s / "lib/ramp.png", s / "soft.png");
  fs::create_symlink(s / "out/forest.exr", s / "to_output.json");  // not there yet
  fs::copy_file(kShippedConfig, s / "cfg.ocio");
  const std::string config = e2e::slurp(s / "cfg.ocio");
  BindMount bind(s / "lib", s / "bound");
  std::vector<std::string> manifests = {s / "lib/ramp.png",
                                        s / "hard.png",
                                        s / "soft.png",
                                        s / "lib/empty/../ramp.png",
                                        s / "out/ramp.exr",
                                        s / "out/./forest.exr",
                                        s / "to_output.json",
                                        s / "cfg.ocio",
                                        "/proc/self/fd/7 7<>" + (s / "lib/ramp.png")};
  if (bind.ok) manifests.push_back(s / "bound/forest.exr");
  for (const std::string& m : manifests) {
    SCOPED_TRACE(m);
    auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q --config " +
                 (s / "cfg.ocio") + " --manifest " + m);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("refusing"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s / "out/ramp.exr")) << "refused before any work";
    for (const auto& [f, bytes] : original) {
      EXPECT_EQ(e2e::slurp(s / f), bytes) << f;
    }
    EXPECT_EQ(e2e::slurp(s / "cfg.ocio"), config);
    EXPECT_TRUE(fs::is_symlink(s / "soft.png"));
  }
  // A data file's copy where another file's output goes: the copy is refused (that file
  // fails, named), the output is the converted one.
  fs::create_directories(s / "lib2");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib2/tex.png");
  write_rgb(s / "lib2/tex_normal.exr", 8, OIIO::TypeHalf, {0.5f, 0.5f, 1.0f});
  auto r = run("ingest " + (s / "lib2") + " -o " + (s / "out2") +
               " -q --data copy --name-pattern '{dir}/{stem}_normal.exr'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const auto m2 = manifest(s / "out2/spectralize-ingest.jsonl");
  EXPECT_EQ(record(m2, "tex.png")["status"], "converted");
  EXPECT_EQ(record(m2, "tex_normal.exr")["status"], "failed");
  EXPECT_NE(record(m2, "tex_normal.exr")["message"].get<std::string>().find("is also the output"),
            std::string::npos);
  EXPECT_GE(e2e::read_exr(s / "out2/tex_normal.exr").channels.size(), 3u + 81u)
      << "the spectral output, not the copy";
  // Links spectralize did not make, inside the destination: a folder link and a file link
  // are never written through; their targets are untouched.
  fs::create_directories(s / "lib3/walls");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib3/walls/w.png");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib3/y.png");
  fs::create_directories(s / "elsewhere");
  fs::create_directories(s / "out3");
  fs::create_symlink(s / "elsewhere", s / "out3/walls");
  std::ofstream(s / "victim.txt") << "precious";
  fs::create_symlink(s / "victim.txt", s / "out3/y.exr");
  r = run("ingest " + (s / "lib3") + " -o " + (s / "out3") + " -q");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("symbolic link spectralize did not make"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(s / "elsewhere"));
  EXPECT_EQ(e2e::slurp(s / "victim.txt"), "precious");
  // The node cache: a link planted at its file is not written through either.
  const std::string cache = s / "cache";
  ASSERT_EQ(run(kImages + "grey_ramp8.png -q -o " + (s / "c1.exr") + " --cache " + cache).exit_code,
            0);
  std::string file;
  for (const auto& e : fs::directory_iterator(cache)) file = e.path().string();
  ASSERT_FALSE(file.empty());
  fs::remove(file);
  std::ofstream(s / "victim2.txt") << "precious too";
  fs::create_symlink(s / "victim2.txt", file);
  r = run(kImages + "grey_ramp8.png -o " + (s / "c2.exr") + " --cache " + cache);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not saved"), std::string::npos) << r.err;
  EXPECT_EQ(e2e::slurp(s / "victim2.txt"), "precious too");
}

// --- The up-to-date key ---

// One case: flags for a rerun and the files it must redo (the rest stay up to date).
struct KeyCase {
  std::string key;   // the schema's setting it exercises
  std::string args;  // added to the baseline's command line
  std::set<std::string> redone;
  bool refused = false;  // a setting that shapes no file of the batch: exit 2, nothing touched
};

// Truth: a rerun redoes exactly the files a changed setting shapes, as resolved for each file
// (the illuminant only reflectances, the emission basis only lights, a mode or colour space
// only where it differs from what the file was decided as), and keeps the others; every
// setting of the schema has a case here (a new one must say what it redoes). The config counts
// by content: the same config by another path (relative, absolute, a link, $OCIO) redoes
// nothing, a changed one everything. An up-to-date record repeats the conversion's warnings.
TEST(Guarantees, UpToDateMeansTheSameFileWouldBeWritten) {
  Scratch s;
  fs::create_directories(s / "lib");
  write_rgb(s / "lib/surface.png", 16, OIIO::TypeUInt8, {0.6f, 0.4f, 0.2f});     // reflectance
  write_rgb(s / "lib/light.exr", 16, OIIO::TypeHalf, {2.0f, 1.5f, 0.5f}, true);  // emission
  fs::copy_file(kShippedConfig, s / "same.ocio");
  fs::create_symlink(s / "same.ocio", s / "link.ocio");
  std::ofstream(s / "changed.ocio") << e2e::slurp(kShippedConfig) << "\n# changed\n";
  const std::set<std::string> all = {"surface.png", "light.exr"};
  const std::set<std::string> none;
  const std::vector<KeyCase> cases = {
      {"colorspace", "--colorspace 'sRGB - Texture'", {"light.exr"}},
      {"mode", "--mode reflectance", {"light.exr"}},
      {"mode", "--mode emission", {"surface.png"}},
      {"wavelengths", "--wavelengths 400:700:10", all},
      {"observer", "--observer cie1964", all},
      {"illuminant", "--illuminant A", {"surface.png"}},
      {"model", "--model smooth", all},
      // The default (exemplar) model has no edge filter and no curvature: refused, not ignored.
      {"filter", "--filter 0.5", none, true},
      {"curvature", "--curvature 5", none, true},
      {"emission_basis", "--emission-basis D65", {"light.exr"}},
      {"format", "--format float", all},
      {"compression", "--compression piz", all},
      {"tile", "--tile 16", all},
      {"preview_colorspace", "--preview-colorspace ACEScg", all},
      {"method", "--method exact", all},
      {"cache", "--cache " + (s / "cache"), none},
      {"threads", "--threads 1", none},
      {"jobs", "--jobs 1", none},
      {"data", "--data copy", none},
      {"data_names", "--data-names +zzz", none},
      {"colour_names", "--colour-names +zzz:emission", none},
      {"colour_names", "--colour-names +surface:emission", {"surface.png"}},  // its mode changes
      {"name_pattern", "", none},              // moves the outputs: not a rerun of the same files
      {"config", "--config same.ocio", none},  // a relative path
      {"config", "--config " + (s / "same.ocio"), none},
      {"config", "--config " + (s / "link.ocio"), none},
      {"config", "--config " + (s / "changed.ocio"), all},
  };
  // Every setting of ingest has a case.
  std::set<std::string> covered;
  for (const KeyCase& c : cases) covered.insert(c.key);
  for (const spectralize::SettingSpec& spec : spectralize::settings_schema())
    if (spec.applies(spectralize::kIngest)) {
      EXPECT_TRUE(covered.count(std::string(spec.key)))
          << "setting '" << spec.key << "' has no case: say which files it redoes";
    }
  // The baseline, kept aside; each case reruns on a fresh copy of it.
  const std::string cd = "cd " + s.dir.string() + " &&";
  auto r = run("ingest lib -o base -q", cd);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto first = manifest(s / "base/spectralize-ingest.jsonl");
  const Json light = record(first, "light.exr");
  ASSERT_TRUE(light.contains("warnings")) << light.dump();
  r = run("ingest lib -o base -q", cd);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto again = manifest(s / "base/spectralize-ingest.jsonl");
  EXPECT_EQ(with_status(again, "up_to_date"), all);
  EXPECT_EQ(record(again, "light.exr")["warnings"], light["warnings"])
      << "an up-to-date record repeats the warnings of the conversion that made the file";
  for (const KeyCase& c : cases) {
    if (c.args.empty()) continue;
    SCOPED_TRACE(c.args);
    fs::remove_all(s / "case");
    fs::copy(s / "base", s / "case", fs::copy_options::recursive);
    r = run("ingest lib -o case -q " + c.args, cd);
    if (c.refused) {
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find("does not shape"), std::string::npos) << r.err;
      EXPECT_EQ(e2e::slurp(s / "case/spectralize-ingest.jsonl"),
                e2e::slurp(s / "base/spectralize-ingest.jsonl"))
          << "nothing touched";
      continue;
    }
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto m = manifest(s / "case/spectralize-ingest.jsonl");
    EXPECT_EQ(with_status(m, "converted"), c.redone);
    std::set<std::string> kept;
    for (const std::string& f : all)
      if (!c.redone.count(f)) kept.insert(f);
    EXPECT_EQ(with_status(m, "up_to_date"), kept);
  }
  // $OCIO naming the same config by another path: nothing redone.
  fs::remove_all(s / "case");
  fs::copy(s / "base", s / "case", fs::copy_options::recursive);
  r = run("ingest lib -o case -q", cd + " OCIO=" + (s / "link.ocio"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(with_status(manifest(s / "case/spectralize-ingest.jsonl"), "up_to_date"), all);
}

// --- Names ---

// Truth: a file name that is not UTF-8 (legal on Linux) works in a batch, a list and a
// single-file run; every manifest and report is valid JSON that names it readably and
// losslessly ("<key>_base64" holds its bytes); the output carries the same bytes.
TEST(Guarantees, NamesAreBytes) {
  Scratch s;
  fs::create_directories(s / "lib");
  const std::string odd = "wall\xff\xfe_basecolor";  // not UTF-8
  fs::copy_file(kImages + "grey_ramp8.png", s / ("lib/" + odd + ".png"));
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/plain.png");
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = manifest(s / "out/spectralize-ingest.jsonl");  // strict JSON
  ASSERT_EQ(m.size(), 3u);
  Json j = record(m, "_basecolor.png");
  ASSERT_TRUE(j.contains("input_base64")) << j.dump();
  EXPECT_EQ(j["input"], s / "lib/wall\\xFF\\xFE_basecolor.png");
  EXPECT_EQ(j["status"], "converted");
  EXPECT_TRUE(fs::exists(s / ("out/" + odd + ".exr")));
  EXPECT_FALSE(record(m, "plain.png").contains("input_base64"));
  // The base64 field holds the bytes (decoded here with Python's standard library).
  {
    std::ofstream(s / "b64") << j["input_base64"].get<std::string>();
    ASSERT_EQ(std::system(("/usr/bin/python3 -c \"import base64,sys; sys.stdout.buffer.write("
                           "base64.b64decode(open('" +
                           (s / "b64") + "').read()))\" > " + (s / "decoded"))
                              .c_str()),
              0);
    EXPECT_EQ(e2e::slurp(s / "decoded"), s / ("lib/" + odd + ".png"));
  }
  // Single files, with a report; a list file naming it.
  r = run("'" + (s / ("lib/" + odd + ".png")) + "' -o '" + (s / ("one" + odd + ".exr")) +
          "' -q --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream rf(s / "r.json");
  const Json rep = Json::parse(rf);
  EXPECT_TRUE(rep.contains("input_base64"));
  EXPECT_TRUE(rep.contains("output_base64"));
  std::ofstream(s / "list.txt") << "lib/" << odd << ".png\n";
  r = run("ingest --inputs-from " + (s / "list.txt") + " -o " + (s / "fromlist") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(manifest(s / "fromlist/spectralize-ingest.jsonl").back()["summary"]["converted"], 1);
}

// --- What the walk leaves out ---

// Truth: everything the walk did not take is named in the manifest with its reason and
// counted in the summary: hidden files, spectralize's temporaries, non-images, links to
// devices, dangling links, FIFOs, the destination reached through a link; a loop and a folder
// that cannot be read are failures of the batch (exit 1). A destination where a pattern looks
// for files is refused like one inside a source folder.
TEST(Guarantees, TheWalkNamesWhatItLeavesOut) {
  Scratch s;
  fs::create_directories(s / "lib/a");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/ramp.png");
  std::ofstream(s / "lib/.hidden.png") << "x";
  std::ofstream(s / "lib/.ramp.exr.spectralize-Ab12Cd.tmp") << "x";
  std::ofstream(s / "lib/notes.txt") << "x";
  fs::create_symlink("/dev/null", s / "lib/device.png");
  fs::create_symlink(s / "nowhere.png", s / "lib/dangling.png");
  ASSERT_EQ(::mkfifo((s / "lib/fifo.png").c_str(), 0600), 0);
  fs::create_symlink(s / "out", s / "lib/to_out");
  fs::create_directories(s / "out");
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q", "timeout 60");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto m = manifest(s / "out/spectralize-ingest.jsonl");
  const std::map<std::string, std::string> kinds = {
      {".hidden.png", "hidden"},         {".ramp.exr.spectralize-Ab12Cd.tmp", "temporary"},
      {"notes.txt", "not_image"},        {"device.png", "not_regular"},
      {"dangling.png", "dangling_link"}, {"fifo.png", "not_regular"},
      {"to_out", "destination"}};
  for (const auto& [name, kind] : kinds) {
    SCOPED_TRACE(name);
    const Json l = record(m, "/" + name, "left_out");
    EXPECT_EQ(l["kind"], kind) << l.dump();
    EXPECT_EQ(l["failure"], false);
  }
  const Json& sum = m.back()["summary"];
  EXPECT_EQ(sum["left_out"], kinds.size());
  EXPECT_EQ(sum["left_out_by_reason"]["not_regular"], 2);
  EXPECT_EQ(sum["converted"], 1);
  // A loop: a failure, named.
  fs::create_symlink(s / "lib", s / "lib/a/loop");
  r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q", "timeout 60");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("a loop"), std::string::npos) << r.err;
  EXPECT_EQ(record(manifest(s / "out/spectralize-ingest.jsonl"), "/loop", "left_out")["failure"],
            true);
  fs::remove(s / "lib/a/loop");
  // A folder that cannot be read (as an unprivileged user when this runs as root).
  fs::create_directories(s / "lib/locked");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/locked/x.png");
  ::chmod((s / "lib/locked").c_str(), 0);
  std::string as_user;
  if (::geteuid() == 0) {
    as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups";
    ::chmod(s.dir.c_str(), 0777);
    fs::remove_all(s / "out");
  }
  if (::geteuid() != 0 || std::system("setpriv --version >/dev/null 2>&1") == 0) {
    r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q", "timeout 60 " + as_user);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("lib/locked"), std::string::npos) << r.err;
    const Json l = record(manifest(s / "out/spectralize-ingest.jsonl"), "/locked", "left_out");
    EXPECT_EQ(l["kind"], "unreadable_folder") << l.dump();
    EXPECT_EQ(l["failure"], true);
  }
  ::chmod((s / "lib/locked").c_str(), 0755);
  // Patterns that look for files in the destination are refused, nothing written.
  for (const std::string& pattern : {"'" + (s / "lib") + "/*'", "'" + (s / "lib") + "/*/*.png'"}) {
    const std::string dest = pattern.find("/*/") != std::string::npos ? s / "lib/a" : s / "lib";
    r = run("ingest " + pattern + " -o " + dest);
    EXPECT_EQ(r.exit_code, 2) << pattern << ": " << r.err;
    EXPECT_NE(r.err.find("outputs would be ingested again"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dest + "/spectralize-ingest.jsonl"));
  }
}

// --- Shards and merges ---

// Truth: one parser for I/N (the CLI, Slurm's variables, part names): anything but I/N with
// 0 <= I < N is refused (exit 2), a stepped Slurm array gives each task its place, garbage is
// an error; a merge takes only one batch's complete parts, each once, with the right totals.
TEST(Guarantees, ShardsAndMergesAreChecked) {
  Scratch s;
  make_library(s);
  // (The parser's unit test tries every kind of slip; these reach it through the CLI.)
  for (const char* spec : {"0/1e3", "0/2x", "0/2/3", "01/2", "2/2"}) {
    auto r = run("ingest " + (s / "lib") + " -o " + (s / "x") + " --shard '" + spec + "'");
    EXPECT_EQ(r.exit_code, 2) << spec << ": " << r.err;
    EXPECT_NE(r.err.find("--shard"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(s / "x"));
  // Slurm: --array=0-10:2 has tasks 0, 2, ..., 10: task 4 is shard 2 of 6.
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "sl") + " -q",
               "SLURM_ARRAY_TASK_ID=4 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_MAX=10 "
               "SLURM_ARRAY_TASK_STEP=2 SLURM_ARRAY_TASK_COUNT=6");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "sl/spectralize-ingest.part-2-of-6.jsonl"));
  // (The parser's unit test tries every shape of array; two reach it through the CLI.)
  for (const char* env : {"SLURM_ARRAY_TASK_ID=abc SLURM_ARRAY_TASK_COUNT=3",
                          "SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=7 "
                          "SLURM_ARRAY_TASK_COUNT=3"}) {
    r = run("ingest " + (s / "lib") + " -o " + (s / "bad") + " -q", env);
    EXPECT_EQ(r.exit_code, 2) << env << ": " << r.err;
    EXPECT_NE(r.err.find("SLURM_ARRAY_TASK"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(s / "bad"));
  // A batch in 2 shards, merged.
  for (int i = 0; i < 2; ++i) {
    ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "sh") + " -q --shard " +
                  std::to_string(i) + "/2")
                  .exit_code,
              0);
  }
  const std::string p0 = s / "sh/spectralize-ingest.part-0-of-2.jsonl";
  const std::string p1 = s / "sh/spectralize-ingest.part-1-of-2.jsonl";
  r = run("ingest --merge -o " + (s / "sh") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto merged = manifest(s / "sh/spectralize-ingest.jsonl");
  EXPECT_EQ(merged.back()["summary"]["files"], 3);
  EXPECT_EQ(merged.back()["summary"]["converted"], 2);
  EXPECT_EQ(merged.back()["summary"]["skipped_data"], 1);
  // Parts that are not one batch's, complete, each once: refused, naming the part.
  const std::string good1 = e2e::slurp(p1);
  struct Bad {
    std::string what, file, content;  // content "" : a folder
  };
  const std::vector<Bad> bad = {
      {"5-of-2", s / "sh/spectralize-ingest.part-5-of-2.jsonl", good1},
      {"an oversized index", s / "sh/spectralize-ingest.part-99999999999999999999-of-2.jsonl",
       good1},
      {"a leading zero", s / "sh/spectralize-ingest.part-01-of-2.jsonl", good1},
      {"empty", p1, " "},
      {"a folder", p1, ""},
      {"cut short", p1, good1.substr(good1.find('\n') + 1)},
      {"no summary", p1, good1.substr(0, good1.rfind("{\"summary\""))},
  };
  for (const Bad& b : bad) {
    SCOPED_TRACE(b.what);
    fs::remove_all(b.file);
    if (b.content.empty())
      fs::create_directory(b.file);
    else
      std::ofstream(b.file) << (b.content == " " ? "" : b.content);
    r = run("ingest --merge -o " + (s / "sh") + " -q");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("part"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("stoi"), std::string::npos) << r.err;
    fs::remove_all(b.file);
    std::ofstream(p1) << good1;
  }
  // A stale part of an earlier batch (the library changed since): refused.
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/new.png");
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "sh") + " -q --shard 0/2").exit_code, 0);
  r = run("ingest --merge -o " + (s / "sh") + " -q");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("another batch"), std::string::npos) << r.err;
}

// --- Exit codes ---

struct ExitCase {
  std::string args, env;
  int code;
  std::string message;  // a piece of stderr
};

// Truth (the guide's "Exit status" (docs/guide/files.md)): 2 for a command line that cannot be run
// as written (a value, an unknown colour space on the command line, a shard), 1 for a job that
// could not be done (a file or config that cannot be read, a file that cannot be written), the same
// in every command; system errors carry the system's reason.
TEST(Guarantees, ExitCodesFollowOnePolicy) {
  Scratch s;
  make_library(s);
  ASSERT_EQ(run(kImages + "grey_ramp8.png -q -o " + (s / "spectral.exr")).exit_code, 0);
  std::ofstream(s / "afile") << "x";
  const std::string in = kImages + "grey_ramp8.png", spectral = s / "spectral.exr";
  const std::string bad_ocio = "OCIO=" + (s / "missing.ocio");
  const std::vector<ExitCase> cases = {
      {in + " -o " + (s / "a.exr") + " --colorspace nosuch", "", 2, "--colorspace"},
      {in + " -o " + (s / "a.exr") + " --preview-colorspace nosuch", "", 2, "--preview-colorspace"},
      {"ingest " + (s / "lib") + " -o " + (s / "o") + " --preview-colorspace nosuch", "", 2,
       "--preview-colorspace"},
      {"--color 1,1,1 --colorspace nosuch", "", 2, "--colorspace"},
      {"--to-rgb " + spectral + " -o " + (s / "t.exr") + " --colorspace nosuch", "", 2,
       "--colorspace"},
      {in + " -o " + (s / "a.exr"), bad_ocio, 1, "missing.ocio"},
      {"--color 1,1,1", bad_ocio, 1, "missing.ocio"},
      {"--color 1,1,1 -o " + (s / "p.svg"), bad_ocio, 1, "missing.ocio"},
      {"--to-rgb " + spectral + " -o " + (s / "t.exr"), bad_ocio, 1, "missing.ocio"},
      {"--plot-pixel 1,1 " + spectral + " -o " + (s / "p.svg"), bad_ocio, 1, "missing.ocio"},
      {"ingest " + (s / "lib") + " -o " + (s / "o"), bad_ocio, 1, "missing.ocio"},
      {in + " -o " + (s / "a.exr") + " --config " + (s / "missing.ocio"), "", 1, "missing.ocio"},
      {"ingest " + (s / "lib") + " -o " + (s / "afile"), "", 1, "is not a folder"},
      {"ingest --merge -o " + (s / "afile"), "", 1, "is not a folder"},
      {(s / "missing.png") + " -o " + (s / "a.exr"), "", 1, "no such file"},
      {in + " -o " + (s / "a.exr") + " --threads x", "", 2, "--threads"},
      {in + " -o " + (s / "big.exr"), "ulimit -f 4;", 1, "File too large"},
  };
  for (const ExitCase& c : cases) {
    auto r = run(c.args, c.env);
    EXPECT_EQ(r.exit_code, c.code) << c.env << " " << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(s / "o"));
  // A full disk: the system's reason, for every kind of writer.
  const std::string mnt = s / "small";
  fs::create_directory(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here; the ulimit -f case covers failing writes";
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
  } unmount{mnt};
  for (const std::string& args : {kImages + "hdri_sunset_256x128.exr -o " + mnt + "/o.exr",
                                  "ingest " + (s / "lib") + " -o " + mnt + "/lib",
                                  "--color 0.2,0.5,0.1 --color 0.1,0.1,0.9 -o " + mnt + "/p.tif"}) {
    std::ofstream(mnt + "/filler") << std::string(1000 * 1024, 'x') << std::flush;
    auto r = run("-q " + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << args << ": " << r.err;
    fs::remove_all(mnt + "/lib");
    fs::remove(mnt + "/filler");
  }
}

// --- Inputs given twice ---

using Identity = std::pair<dev_t, ino_t>;

// Truth: one file given twice (the same folder twice, "lib ./lib/", a file and a link to it)
// is one input: converted once, the repeat named in the manifest, exit 0.
TEST(Guarantees, OneFileGivenTwiceIsOneInput) {
  Scratch s;
  make_library(s);
  fs::create_symlink(s / "lib/ramp.png", s / "link.png");
  const std::string cd = "cd " + s.dir.string() + " &&";
  for (const std::string& sources :
       std::vector<std::string>{"lib lib", "lib ./lib/", "lib/ramp.png lib/ramp.png",
                                "lib/ramp.png link.png", "lib " + (s / "lib/forest.exr")}) {
    SCOPED_TRACE(sources);
    fs::remove_all(s / "out");
    auto r = run("ingest " + sources + " -o out -q", cd);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto m = manifest(s / "out/spectralize-ingest.jsonl");
    const Json& sum = m.back()["summary"];
    EXPECT_EQ(sum["failed"], 0);
    // The repeat is named: the same folder (walked once) or the same file (taken once).
    EXPECT_EQ(sum["left_out"], 1) << sum.dump();
    std::set<Identity> inputs;
    for (const Json& rec : m)
      if (rec.contains("status")) {
        EXPECT_NE(rec["status"], "failed") << rec.dump();
        struct stat st = {};
        ASSERT_EQ(::stat((s.dir / rec["input"].get<std::string>()).c_str(), &st), 0);
        EXPECT_TRUE(inputs.insert({st.st_dev, st.st_ino}).second) << rec.dump();
      }
  }
}

// --- The cost of a file ---

// Truth (the guide's "What a file costs" (docs/guide/ingest.md)): a batch of files does once
// what need not be done per file, counted where it happens (core/work_counts.h), not timed: 300
// copies of one 8x8 image parse no config while converting (the plan parsed it), build one
// spectralizer, open each input once (its decision and its conversion share the reader) and ask
// OCIO's file rules only about the names a rule can match (the shipped config's rules: "_srgb",
// "_linear", ".hdr"), each once. The time per file is measured by make bench
// (tests/bench/bench_tiny_files.sh), never asserted.
TEST(Guarantees, TinyFilesDoOnceWhatNeedNotBeDonePerFile) {
  Scratch s;
  fs::create_directories(s / "tiny");
  write_rgb(s / "tiny/t.png", 8, OIIO::TypeUInt8, {0.3f, 0.5f, 0.7f});
  constexpr int kFiles = 300, kRuled = 20;  // of them, named for a file rule
  for (int i = 1; i < kFiles; ++i)
    fs::copy_file(s / "tiny/t.png",
                  s / ("tiny/t" + std::to_string(i) + (i <= kRuled ? "_srgb.png" : ".png")));
  const auto r = run("ingest " + (s / "tiny") + " -o " + (s / "out") + " -q --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json sum = manifest(s / "out/spectralize-ingest.jsonl").back()["summary"];
  EXPECT_EQ(sum["converted"], kFiles);
  const Json& work = sum["work"];
  EXPECT_EQ(work["configs_parsed"], 0) << work.dump();
  EXPECT_EQ(work["spectralizers_built"], 1) << work.dump();
  EXPECT_EQ(work["inputs_opened"], kFiles) << work.dump();
  EXPECT_EQ(work["file_rule_matches"], kRuled) << work.dump();
  // The rule decided those files (the screen passed them to OCIO), and only those.
  int ruled = 0;
  for (const Json& rec : manifest(s / "out/spectralize-ingest.jsonl"))
    if (rec.contains("colorspace_reason") &&
        rec["colorspace_reason"].get<std::string>().find("file rule 'sRGB'") != std::string::npos)
      ++ruled;
  EXPECT_EQ(ruled, kRuled);
  // A rerun opens no input: each output is up to date from its header alone.
  const auto again = run("ingest " + (s / "tiny") + " -o " + (s / "out") + " -q --jobs 2");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const Json rerun = manifest(s / "out/spectralize-ingest.jsonl").back()["summary"];
  EXPECT_EQ(rerun["up_to_date"], kFiles);
  EXPECT_EQ(rerun["work"]["inputs_opened"], 0) << rerun.dump();
  EXPECT_EQ(rerun["work"]["spectralizers_built"], 0) << rerun.dump();
}

}  // namespace
