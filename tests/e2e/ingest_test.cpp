// `spectralize ingest` through the real binary: decisions with reasons, data maps never
// spectralized, mirrored outputs, up-to-date reruns, interrupted batches that finish on rerun,
// bad inputs that do not stop the others, shards and their merge. The oracles are the file
// system, the manifest read as JSON, and the outputs read back with OIIO.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_ingest") {}
};

// A small library: textures by name, data maps, lights, a non-image file, in folders.
void make_library(const Scratch& s) {
  fs::create_directories(s / "lib/walls");
  fs::create_directories(s / "lib/sky");
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/walls/brick_BaseColor.png");
  fs::copy_file(kImages + "colorchecker_srgb16.png", s / "lib/walls/brick_albedo_srgb.png");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/walls/brick_Normal.png");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/walls/brick-roughness.png");
  fs::copy_file(kImages + "hdri_sunset_256x128.exr", s / "lib/sky/sunset_hdri.exr");
  fs::copy_file(kImages + "hdri_forest_256x128.exr", s / "lib/sky/forest.exr");
  std::ofstream(s / "lib/notes.txt") << "not an image";
}

std::vector<Json> manifest(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

// The record whose `key` (a path) ends in `suffix`.
Json record_of(const std::vector<Json>& m, const std::string& key, const std::string& suffix) {
  for (const Json& r : m)
    if (r.contains(key) && r[key].get<std::string>().size() >= suffix.size() &&
        r[key].get<std::string>().rfind(suffix) == r[key].get<std::string>().size() - suffix.size())
      return r;
  return Json();
}

Json record(const std::vector<Json>& m, const std::string& input_suffix) {
  return record_of(m, "input", input_suffix);
}

TEST(Ingest, DecidesEachFileWithItsReasonAndMirrorsTheTree) {
  Scratch s;
  make_library(s);
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = manifest(s / "out/spectralize-ingest.jsonl");
  ASSERT_EQ(m.size(), 8u);  // six images, the .txt left out (not an image), the summary
  EXPECT_EQ(record_of(m, "left_out", "notes.txt")["kind"], "not_image");
  Json j = record(m, "brick_BaseColor.png");
  EXPECT_EQ(j["status"], "converted");
  EXPECT_EQ(j["output"], s / "out/walls/brick_BaseColor.exr");
  EXPECT_EQ(j["mode"], "reflectance");
  EXPECT_NE(j["mode_reason"].get<std::string>().find("name word 'basecolor'"), std::string::npos);
  EXPECT_EQ(j["colorspace"], "sRGB - Texture");
  j = record(m, "brick_albedo_srgb.png");
  EXPECT_EQ(j["colorspace_reason"], "the config's file rule 'sRGB'");
  for (const char* data : {"brick_Normal.png", "brick-roughness.png"}) {
    j = record(m, data);
    EXPECT_EQ(j["status"], "skipped_data") << data;
    EXPECT_NE(j["reason"].get<std::string>().find("data by its name word"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(s / "out/walls/brick_Normal.exr"));
  j = record(m, "sunset_hdri.exr");
  EXPECT_EQ(j["mode"], "emission");
  EXPECT_NE(j["mode_reason"].get<std::string>().find("name word 'hdri'"), std::string::npos);
  j = record(m, "forest.exr");  // no word in its name: its folder's, sky/
  EXPECT_EQ(j["mode"], "emission");
  EXPECT_NE(j["mode_reason"].get<std::string>().find("folder word 'sky'"), std::string::npos);
  const Json& sum = m.back()["summary"];
  EXPECT_EQ(sum["converted"], 4);
  EXPECT_EQ(sum["skipped_data"], 2);
  EXPECT_EQ(sum["failed"], 0);
  // The outputs are the single-file command's, byte for byte but for the recorded source.
  const e2e::Exr batch = e2e::read_exr(s / "out/walls/brick_BaseColor.exr");
  ASSERT_EQ(run(s / "lib/walls/brick_BaseColor.png" + std::string(" -q -o ") + (s / "one.exr") +
                " --mode reflectance")
                .exit_code,
            0);
  const e2e::Exr single = e2e::read_exr(s / "one.exr");
  EXPECT_EQ(batch.pixels, single.pixels);
  // Data maps copied unchanged on request.
  r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " --data copy -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(e2e::slurp(s / "out/walls/brick_Normal.png"),
            e2e::slurp(s / "lib/walls/brick_Normal.png"));
  // A data colour space by the config marks a file as data too.
  r = run("ingest " + (s / "lib/sky/forest.exr") + " -o " + (s / "raw") + " --colorspace Raw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(record(manifest(s / "raw/spectralize-ingest.jsonl"), "forest.exr")["status"],
            "skipped_data");
}

// Truth: a rerun with nothing changed converts nothing and opens no input (each output is up to
// date from its header alone, counted in the summary's work); a touched input and changed
// settings are converted again; --force redoes everything.
TEST(Ingest, RerunsSkipWhatIsUpToDate) {
  Scratch s;
  make_library(s);
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q").exit_code, 0);
  const auto mtime = fs::last_write_time(s / "out/walls/brick_BaseColor.exr");
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto m = manifest(s / "out/spectralize-ingest.jsonl");
  EXPECT_EQ(m.back()["summary"]["up_to_date"], 4);
  EXPECT_EQ(m.back()["summary"]["converted"], 0);
  EXPECT_EQ(fs::last_write_time(s / "out/walls/brick_BaseColor.exr"), mtime);
  // Not rewritten (the time above), and not even opened as images: a stat and a header read.
  EXPECT_EQ(m.back()["summary"]["work"]["inputs_opened"], 0) << m.back().dump();
  EXPECT_EQ(m.back()["summary"]["work"]["spectralizers_built"], 0) << m.back().dump();
  // The input changes: converted again.
  fs::last_write_time(
      s / "lib/walls/brick_BaseColor.png",
      fs::last_write_time(s / "lib/walls/brick_BaseColor.png") + std::chrono::seconds(5));
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q").exit_code, 0);
  m = manifest(s / "out/spectralize-ingest.jsonl");
  EXPECT_EQ(record(m, "brick_BaseColor.png")["status"], "converted");
  EXPECT_EQ(m.back()["summary"]["converted"], 1);
  // Settings that change the spectra: everything again; --force: everything again.
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q --wavelengths 400:700:10")
                .exit_code,
            0);
  EXPECT_EQ(manifest(s / "out/spectralize-ingest.jsonl").back()["summary"]["converted"], 4);
  ASSERT_EQ(
      run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q --wavelengths 400:700:10 --force")
          .exit_code,
      0);
  EXPECT_EQ(manifest(s / "out/spectralize-ingest.jsonl").back()["summary"]["converted"], 4);
}

// Truth: a rerun's records say how each file was decided, as the first run's did (read back
// from the output's header), and a data file that was skipped names no output.
TEST(Ingest, RerunRecordsSayHowEachFileWasDecided) {
  Scratch s;
  make_library(s);
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q").exit_code, 0);
  const auto first = manifest(s / "out/spectralize-ingest.jsonl");
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q").exit_code, 0);
  const auto again = manifest(s / "out/spectralize-ingest.jsonl");
  for (const char* name :
       {"brick_BaseColor.png", "brick_albedo_srgb.png", "sunset_hdri.exr", "forest.exr"}) {
    SCOPED_TRACE(name);
    const Json a = record(first, name), b = record(again, name);
    ASSERT_EQ(a["status"], "converted");
    ASSERT_EQ(b["status"], "up_to_date");
    for (const char* key : {"colorspace", "colorspace_reason", "mode", "mode_reason"}) {
      EXPECT_EQ(b[key], a[key]) << key;
    }
  }
  const Json data = record(again, "brick_Normal.png");
  EXPECT_EQ(data["status"], "skipped_data");
  EXPECT_FALSE(data.contains("output"));
}

// Truth: texture names put the map's kind last, so a colour word after a data word is a colour
// map ("metal_plate_basecolor"), a data word after a colour word is data ("albedo_roughness").
TEST(Ingest, TheLastWordOfTheNameSaysWhatTheMapIs) {
  Scratch s;
  fs::create_directories(s / "lib");
  for (const char* name : {"metal_plate_basecolor.png", "rough_stone_albedo.png",
                           "mask_painted_diffuse.png", "albedo_roughness.png", "sky_hdri_mask.png"})
    fs::copy_file(kImages + "colorchecker_srgb8.png", s / ("lib/" + std::string(name)));
  ASSERT_EQ(run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q").exit_code, 0);
  const auto m = manifest(s / "out/spectralize-ingest.jsonl");
  for (const char* colour :
       {"metal_plate_basecolor.png", "rough_stone_albedo.png", "mask_painted_diffuse.png"}) {
    EXPECT_EQ(record(m, colour)["status"], "converted") << colour;
    EXPECT_EQ(record(m, colour)["mode"], "reflectance") << colour;
  }
  EXPECT_NE(record(m, "albedo_roughness.png")["reason"].get<std::string>().find("'roughness'"),
            std::string::npos);
  EXPECT_NE(record(m, "sky_hdri_mask.png")["reason"].get<std::string>().find("'mask'"),
            std::string::npos);
}

// Truth: glob patterns mirror the folders below their fixed part, and a pattern that matches
// nothing is that input's failure (exit 1, named), not a silent success.
TEST(Ingest, GlobsMirrorTheirFoldersAndEmptyOnesFail) {
  Scratch s;
  make_library(s);
  auto r = run("ingest '" + (s / "lib") + "/*/*.png' -o " + (s / "out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "out/walls/brick_BaseColor.exr"));
  EXPECT_FALSE(fs::exists(s / "out/brick_BaseColor.exr"));
  r = run("ingest '" + (s / "lib") + "/*/*.tif' " + (s / "lib/sky/forest.exr") + " -o " +
          (s / "out2") + " -q");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("*.tif"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("matches no image file"), std::string::npos) << r.err;
  const auto m = manifest(s / "out2/spectralize-ingest.jsonl");
  EXPECT_EQ(record(m, "forest.exr")["status"], "converted");
  EXPECT_EQ(m.back()["summary"]["failed"], 1);
}

// Truth: the temporaries that killed runs left anywhere in the output folders (outputs, data
// copies, names cut to fit NAME_MAX) are removed by the next run, and a live writer's
// temporary (locked) is never touched.
TEST(Ingest, StaleTemporariesOfAnyOutputGoLiveOnesStay) {
  Scratch s;
  make_library(s);
  fs::create_directories(s / "out/walls");
  const std::string long_name = "." + std::string(200, 'x') + ".spectralize-Ab12Cd.tmp";
  const std::vector<std::string> stale = {
      s / "out/walls/.brick_Normal.png.spectralize-AbC123.tmp",
      s / "out/walls/.anything.exr.spectralize-q9Z8y7.tmp", s / ("out/walls/" + long_name),
      s / "out/.spectralize-ingest.jsonl.spectralize-Q1w2E3.tmp"};
  for (const auto& f : stale) std::ofstream(f) << "left by a killed run";
  // A live writer: a process holding the lock of its temporary.
  const std::string live = s / "out/walls/.other.exr.spectralize-L1v3W7.tmp";
  std::ofstream(live) << "being written";
  const std::string keep = s / "out/walls/.notes.tmp";  // not ours
  std::ofstream(keep) << "a user's file";
  // It says so through a pipe once it holds the lock (a handshake, not a sleep).
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t holder = fork();
  if (holder == 0) {
    ::close(ready[0]);
    const int fd = ::open(live.c_str(), O_RDONLY);
    ::flock(fd, LOCK_EX);
    (void)!::write(ready[1], "1", 1);
    ::pause();
    ::_exit(0);
  }
  ::close(ready[1]);
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1) << "the lock holder did not start";
  ::close(ready[0]);
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " --data copy -q");
  ::kill(holder, SIGKILL);
  ::waitpid(holder, nullptr, 0);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& f : stale) {
    EXPECT_FALSE(fs::exists(f)) << f;
  }
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(keep));
  EXPECT_EQ(
      manifest(s / "out/spectralize-ingest.jsonl").back()["summary"]["stale_temporaries_removed"],
      4);
}

// Truth: a batch killed at any moment (SIGINT, SIGTERM, SIGKILL) finishes on rerun, and the
// rerun leaves no temporary or partial file.
TEST(IngestSlow, KilledBatchesFinishOnRerun) {
  Scratch s;
  fs::create_directories(s / "lib");
  for (int i = 0; i < 6; ++i)
    fs::copy_file(kImages + "hdri_interior_1024x512.exr",
                  s / ("lib/map" + std::to_string(i) + ".exr"));
  for (int sig : {SIGINT, SIGTERM, SIGKILL}) {
    SCOPED_TRACE(sig);
    fs::remove_all(s / "out");
    const pid_t pid = fork();
    if (pid == 0) {
      const int devnull = ::open("/dev/null", O_WRONLY);
      ::dup2(devnull, 2);
      const std::string lib = s / "lib", out = s / "out";
      ::execl(SPECTRALIZE_BINARY, SPECTRALIZE_BINARY, "ingest", lib.c_str(), "-o", out.c_str(),
              "--jobs", "1", static_cast<char*>(nullptr));
      _exit(127);
    }
    // Kill it while the second file is being written.
    const auto t0 = std::chrono::steady_clock::now();
    while (!fs::exists(s / "out/map0.exr") &&
           std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto m = manifest(s / "out/spectralize-ingest.jsonl");
    EXPECT_GE(m.back()["summary"]["up_to_date"].get<int>(), 1);
    EXPECT_EQ(
        m.back()["summary"]["up_to_date"].get<int>() + m.back()["summary"]["converted"].get<int>(),
        6);
    for (const auto& e : fs::directory_iterator(s / "out")) {
      EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    }
    for (int i = 0; i < 6; ++i) {
      EXPECT_EQ(e2e::read_exr(s / ("out/map" + std::to_string(i) + ".exr")).width, 1024);
    }
  }
}

// Bad inputs: each gets a message naming the file; the others carry on; exit 1. Wrong command
// lines: exit 2 with nothing written.
TEST(Ingest, BadInputsDoNotStopTheOthers) {
  Scratch s;
  make_library(s);
  std::ofstream(s / "lib/walls/broken.png") << "not a png";
  fs::create_directories(s / "flat");
  fs::copy_file(kImages + "grey_ramp8.png", s / "flat/a.png");
  fs::copy_file(kImages + "grey_ramp8.png", s / "flat/a.jpg");  // same stem: both kept
  // A second source tree with the same name: a.png twice, even with its extension.
  fs::create_directories(s / "flat2");
  fs::copy_file(kImages + "grey_ramp8.png", s / "flat2/a.png");
  auto r = run("ingest " + (s / "lib") + " " + (s / "flat") + " " + (s / "flat2") + " " +
               (s / "missing.png") + " -o " + (s / "out") + " -q");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("broken.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.png"), std::string::npos) << r.err;
  const auto m = manifest(s / "out/spectralize-ingest.jsonl");
  EXPECT_EQ(record(m, "broken.png")["status"], "failed");
  EXPECT_EQ(record(m, "missing.png")["status"], "failed");
  EXPECT_EQ(record(m, "flat/a.png")["status"], "failed");
  EXPECT_NE(record(m, "flat2/a.png")["message"].get<std::string>().find("would all be written"),
            std::string::npos);
  EXPECT_EQ(record(m, "flat/a.jpg")["status"], "converted");
  EXPECT_EQ(record(m, "flat/a.jpg")["output"], s / "out/a.jpg.exr");
  EXPECT_EQ(record(m, "brick_BaseColor.png")["status"], "converted");
  EXPECT_FALSE(fs::exists(s / "out/a.exr"));
  EXPECT_FALSE(fs::exists(s / "out/a.png.exr"));
  // Wrong command lines.
  for (const std::string& args :
       {"ingest " + (s / "lib") + " -o " + (s / "lib/out"),
        "ingest " + (s / "lib") + " -o " + (s / "o2") + " --shard 3/2",
        "ingest " + (s / "lib") + " -o " + (s / "o2") + " --shard 0/0", "ingest -o " + (s / "o2"),
        "ingest " + (s / "lib") + " -o " + (s / "o2") + " --name-pattern {stem}.png"}) {
    r = run(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(s / "lib/out"));
  EXPECT_FALSE(fs::exists(s / "o2"));
  std::ofstream(s / "list.txt") << "lib/walls/brick_BaseColor.png\n{\"input\": 3}\n";
  r = run("ingest --inputs-from " + (s / "list.txt") + " -o " + (s / "o3"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
  // An output folder that cannot be created: that file fails, naming it.
  std::ofstream(s / "blocker") << "a file where a folder should be";
  r = run("ingest " + (s / "lib/sky") + " -o " + (s / "blocker/out") + " -q");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("blocker"), std::string::npos) << r.err;
}

// A list line that states what its file is: the words of its name do not make it data; its
// origin is recorded, its reasons are the decision's, its "where" names a failure.
TEST(Ingest, AListLineStatesWhatItsFileIsAndWhereItComesFrom) {
  Scratch s;
  make_library(s);
  std::ofstream(s / "list.txt")
      << R"({"input": "lib/walls/brick_Normal.png", "mode": "reflectance", "origin": )"
      << R"({"where": "</M/Tex>.inputs:file", "mode_reason": "feeds diffuseColor"}})"
      << "\n"
      << R"({"input": "lib/walls/brick-roughness.png"})"
      << "\n"
      << R"({"input": "lib/walls/lost.png", "origin": {"where": "</M/Lost>.inputs:file"}})"
      << "\n";
  auto r = run("ingest --inputs-from " + (s / "list.txt") + " -o " + (s / "o") + " -q");
  EXPECT_EQ(r.exit_code, 1) << r.err;  // the lost file
  EXPECT_NE(r.err.find("lost.png"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(</M/Lost>.inputs:file)"), std::string::npos) << r.err;
  const auto m = manifest(s / "o/spectralize-ingest.jsonl");
  const Json normal = record(m, "brick_Normal.png");
  EXPECT_EQ(normal["status"], "converted") << normal.dump();
  EXPECT_EQ(normal["mode_reason"], "feeds diffuseColor");
  EXPECT_EQ(normal["origin"]["where"], "</M/Tex>.inputs:file");
  // Its header records the same reason: an up-to-date record reads it back.
  r = run("ingest --inputs-from " + (s / "list.txt") + " -o " + (s / "o") + " -q");
  EXPECT_EQ(record(manifest(s / "o/spectralize-ingest.jsonl"), "brick_Normal.png")["mode_reason"],
            "feeds diffuseColor");
  // A line that states nothing: the name's data word decides, as for any file.
  EXPECT_EQ(record(m, "brick-roughness.png")["status"], "skipped_data");
  EXPECT_EQ(record(m, "lost.png")["origin"]["where"], "</M/Lost>.inputs:file");
}

// A colour space given for a file that its own tag contradicts: both named, the given one
// followed; a file that says nothing of itself, or agrees, has no contradiction.
TEST(Ingest, AGivenSpaceTheFileContradictsIsNamedAndFollowed) {
  Scratch s;
  fs::create_directories(s / "lib");
  e2e::write_image(
      s / "lib/tagged.exr", 4, 4, {"R", "G", "B"}, OIIO::TypeFloat, {}, 0.3f,
      [](OIIO::ImageSpec& spec) { spec.attribute("colorInteropID", "lin_rec709_scene"); });
  e2e::write_image(
      s / "lib/agrees.exr", 4, 4, {"R", "G", "B"}, OIIO::TypeFloat, {}, 0.3f,
      [](OIIO::ImageSpec& spec) { spec.attribute("colorInteropID", "lin_ap1_scene"); });
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/plain.png");
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "o") + " -q --colorspace ACEScg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = manifest(s / "o/spectralize-ingest.jsonl");
  const Json tagged = record(m, "tagged.exr");
  EXPECT_EQ(tagged["colorspace"], "ACEScg");
  EXPECT_EQ(tagged["contradiction"],
            "its file metadata colorInteropID 'lin_rec709_scene' says 'Linear Rec.709 (sRGB)', "
            "but --colorspace says 'ACEScg': 'ACEScg' is followed")
      << tagged.dump();
  EXPECT_FALSE(record(m, "agrees.exr").contains("contradiction"));
  EXPECT_FALSE(record(m, "plain.png").contains("contradiction"));
}

// A list file with per-file settings, and shards whose manifests merge into the batch's.
TEST(Ingest, ListsShardsAndMerge) {
  Scratch s;
  make_library(s);
  std::ofstream(s / "list.txt")
      << "# per-file settings\nlib/walls/brick_BaseColor.png\n"
         "{\"input\": \"lib/sky/forest.exr\", \"wavelengths\": \"400:700:10\"}\n";
  auto r = run("ingest --inputs-from " + (s / "list.txt") + " -o " + (s / "o") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(e2e::read_exr(s / "o/lib/sky/forest.exr").channels.size(), 3u + 31u);
  EXPECT_EQ(e2e::read_exr(s / "o/lib/walls/brick_BaseColor.exr").channels.size(), 3u + 81u);
  for (int i = 0; i < 3; ++i) {
    r = run("ingest " + (s / "lib") + " -o " + (s / "sh") + " -q --shard " + std::to_string(i) +
            "/3");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  // The same split from Slurm's array variables.
  r = run("ingest " + (s / "lib") + " -o " + (s / "sl") + " -q",
          "SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_MIN=4 SLURM_ARRAY_TASK_COUNT=3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "sl/spectralize-ingest.part-1-of-3.jsonl"));
  EXPECT_EQ(manifest(s / "sl/spectralize-ingest.part-1-of-3.jsonl").size(),
            manifest(s / "sh/spectralize-ingest.part-1-of-3.jsonl").size());
  r = run("ingest --merge -o " + (s / "sh"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = manifest(s / "sh/spectralize-ingest.jsonl");
  EXPECT_EQ(m.size(), 8u);  // six files, the .txt left out, the summary
  EXPECT_EQ(m.back()["summary"]["converted"], 4);
  fs::remove(s / "sh/spectralize-ingest.part-2-of-3.jsonl");
  r = run("ingest --merge -o " + (s / "sh"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("shards 2 of 3"), std::string::npos) << r.err;
}

// Truth: a batch holds one shared node table: the cache file it leaves serves a second batch
// without a node solve, and two batches on one cache folder at once leave an intact cache.
TEST(Ingest, OneSharedCache) {
  Scratch s;
  make_library(s);
  const std::string cache = s / "cache";
  const std::string bin = SPECTRALIZE_BINARY;
  const std::string cmd = bin + " ingest " + (s / "lib") + " -o " + (s / "a") + " -q --cache " +
                          cache + " & " + bin + " ingest " + (s / "lib") + " -o " + (s / "b") +
                          " -q --cache " + cache + " & wait";
  ASSERT_EQ(std::system(("sh -c '" + cmd + "'").c_str()), 0);
  auto r = run(s / "lib/walls/brick_BaseColor.png" + std::string(" -o ") + (s / "x.exr") +
               " --mode reflectance -v --cache " + cache);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("cache: 0 nodes computed"), std::string::npos) << r.err;
}

}  // namespace

// Truth: the batch's cores go to the files still converting: with --jobs 2 --threads 2 and one
// file of two to redo, that file converts on both (its record says so).
TEST(Ingest, TheCoresGoToTheFilesStillConverting) {
  Scratch s;
  fs::create_directories(s / "lib");
  fs::copy_file(kImages + "colorchecker_srgb8.png", s / "lib/a_basecolor.png");
  fs::copy_file(kImages + "grey_ramp8.png", s / "lib/b_basecolor.png");
  const std::string cmd =
      "ingest " + (s / "lib") + " -o " + (s / "out") + " --jobs 2 --threads 2 -q";
  ASSERT_EQ(run(cmd).exit_code, 0);
  fs::copy_file(kImages + "colorchecker_srgb16.png", s / "lib/b_basecolor.png",
                fs::copy_options::overwrite_existing);
  ASSERT_EQ(run(cmd).exit_code, 0);
  const std::vector<Json> m = manifest(s / "out/spectralize-ingest.jsonl");
  EXPECT_EQ(record(m, "a_basecolor.png")["status"], "up_to_date");
  EXPECT_EQ(record(m, "b_basecolor.png")["status"], "converted");
  EXPECT_EQ(record(m, "b_basecolor.png")["threads"], 2);
}
