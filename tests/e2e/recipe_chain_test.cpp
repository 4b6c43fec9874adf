// Chains of .spectral recipes (a recipe whose source is a recipe ...): every reader refuses a
// chain deeper than the limit or a loop with one clear message naming the chain's first recipe
// (spectralize, ingest, stock iinfo / oiiotool, OpenImageIO's Python binding), and a crash that
// still happens (the limit raised for the test until the stack overflows) removes the run's
// temporary files and dies of SIGSEGV (docs/DESIGN.md §9).

#include <gtest/gtest.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "cli_support.h"

namespace fs = std::filesystem;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";
// Exported, so that it reaches every command of a line ("ulimit ...; spectralize ...").
const std::string kPluginEnv =
    "export OIIO_LIBRARY_PATH=" SPECTRALIZE_PLUGIN_DIR " " SPECTRALIZE_TOOL_ENV ";";
constexpr int kLimit = 16;  // the documented chain limit (docs/guide/files.md, docs/DESIGN.md §9)

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_chain") {}
};

// The opens of the files in a folder, counted by the kernel (inotify IN_OPEN) from construction
// until counts(): an oracle of how often each level of a chain is read that no load slows.
class OpenCounter {
 public:
  explicit OpenCounter(const fs::path& folder)
      : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)),
        wd_(::inotify_add_watch(fd_, folder.c_str(), IN_OPEN | IN_Q_OVERFLOW)) {}
  ~OpenCounter() { ::close(fd_); }
  bool watching() const { return fd_ >= 0 && wd_ >= 0; }
  /// Opens per file name since construction; "(overflow)" when the kernel dropped events.
  std::map<std::string, int> counts() {
    std::map<std::string, int> n;
    alignas(inotify_event) char buf[1 << 16];
    for (ssize_t got; (got = ::read(fd_, buf, sizeof buf)) > 0;)
      for (char* p = buf; p < buf + got;) {
        const auto* e = reinterpret_cast<const inotify_event*>(p);
        ++n[e->mask & IN_Q_OVERFLOW ? "(overflow)" : e->len ? e->name : "(folder)"];
        p += sizeof(inotify_event) + e->len;
      }
    return n;
  }

 private:
  int fd_, wd_;
};

// A shell command with the plugin on OIIO's search path; exit 128 + N when killed by signal N.
e2e::Run sh(const std::string& command) {
  static int counter = 0;
  const std::string base = std::string(::testing::TempDir()) + "chain_sh_" +
                           std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string cmd =
      "(" + kPluginEnv + " " + command + ") >" + base + ".out 2>" + base + ".err";
  const int status = std::system(cmd.c_str());
  e2e::Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = e2e::slurp(base + ".out");
  r.err = e2e::slurp(base + ".err");
  fs::remove(base + ".out");
  fs::remove(base + ".err");
  return r;
}

// c/r00000.spectral -> c/r00001.spectral -> ... -> c/r<n-1>.spectral -> grey_ramp8.png: n
// recipes, alternately to spectral (the last) and back to RGB, so that every level is a valid
// recipe of its source; returns the first.
std::string make_chain(const Scratch& s, int n) {
  fs::create_directories(s.dir / "c");
  auto name = [](int i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "r%05d.spectral", i);
    return std::string(buf);
  };
  for (int i = 0; i < n; ++i) {
    const std::string source = i + 1 < n ? name(i + 1) : kImages + "grey_ramp8.png";
    const bool to_rgb = (n - 1 - i) % 2 == 1;
    std::ofstream(s.dir / "c" / name(i))
        << "{\"source\": \"" << source << "\"" << (to_rgb ? ", \"to\": \"rgb\"" : "") << "}";
  }
  return (s.dir / "c" / name(0)).string();
}

std::vector<std::string> temporaries_under(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(".spectralize-") != std::string::npos)
      out.push_back(e.path().string());
  return out;
}

// The message every reader gives for a chain past the limit: the first recipe, the limit.
void expect_chain_refusal(const e2e::Run& r, const std::string& first, const std::string& who) {
  const std::string all = r.out + r.err;
  EXPECT_NE(
      all.find("'" + first + "': a chain of more than " + std::to_string(kLimit) + " recipes"),
      std::string::npos)
      << who << ": " << all;
}

// The reproduction of the crash (2500 recipes segfaulted every reader) and one past the limit:
// a clear refusal from every reader, quickly (only kLimit + 1 recipes are opened).
TEST(RecipeChain, DeeperThanTheLimitIsRefusedByEveryReader) {
  Scratch s;
  std::string first = make_chain(s, kLimit + 1);
  auto r = sh(std::string(SPECTRALIZE_BINARY) + " " + first + " -o " + (s / "o.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  expect_chain_refusal(r, first, "spectralize");
  EXPECT_FALSE(fs::exists(s / "o.exr"));
  // The reproduction: 2500 recipes crashed every reader.
  fs::remove_all(s.dir / "c");
  first = make_chain(s, 2500);
  r = sh(std::string(SPECTRALIZE_BINARY) + " " + first + " -o " + (s / "o.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  expect_chain_refusal(r, first, "spectralize");
  EXPECT_FALSE(fs::exists(s / "o.exr"));
  r = sh("iinfo " + first);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << "a crash: " << r.err;
  expect_chain_refusal(r, first, "iinfo");
  r = sh("oiiotool " + first + " -o " + (s / "o.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << "a crash: " << r.err;
  expect_chain_refusal(r, first, "oiiotool");
  EXPECT_FALSE(fs::exists(s / "o.exr"));
  r = sh("/usr/bin/python3 -c \"import OpenImageIO as o; i = o.ImageInput.open('" + first +
         "'); print('opened' if i else o.geterror())\"");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("opened"), std::string::npos) << r.out;
  expect_chain_refusal(r, first, "python OpenImageIO");
  // At the limit the chain is read, by the CLI and by oiiotool alike, each level opened as
  // often as the first: a constant number of times per read of the level above, counted by the
  // kernel (a level read twice, to decide light or surface, opened the deepest 2^15 times).
  fs::remove_all(s.dir / "c");
  first = make_chain(s, kLimit);
  for (const std::string& reader :
       {std::string(SPECTRALIZE_BINARY) + " -q", std::string("oiiotool")}) {
    SCOPED_TRACE(reader);
    OpenCounter opens(s.dir / "c");
    ASSERT_TRUE(opens.watching());
    fs::remove(s / "o.exr");
    r = sh(reader + " " + first + " -o " + (s / "o.exr"));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::map<std::string, int> n = opens.counts();
    ASSERT_EQ(n.count("(overflow)"), 0u);
    const int top = n.count("r00000.spectral") ? n.at("r00000.spectral") : 0;
    EXPECT_GE(top, 1);
    std::string all;
    for (const auto& [name, count] : n) all += name + ": " + std::to_string(count) + "\n";
    for (const auto& [name, count] : n) EXPECT_LE(count, top) << all;
  }
}

// In a batch the over-deep recipe is one failed file, recorded in the manifest, not a crash.
TEST(RecipeChain, IngestRecordsTheChainAsAFailedFile) {
  Scratch s;
  const std::string first = make_chain(s, 2500);
  fs::create_directories(s.dir / "src");
  fs::copy_file(kImages + "grey_ramp8.png", s.dir / "src" / "ramp.png");
  auto r = sh(std::string(SPECTRALIZE_BINARY) + " ingest -q " + first + " " + (s / "src") + " -o " +
              (s / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.err;  // one file failed
  const std::string manifest = e2e::slurp(s / "out/spectralize-ingest.jsonl");
  EXPECT_NE(manifest.find("a chain of more than 16 recipes"), std::string::npos) << manifest;
  EXPECT_TRUE(fs::exists(s / "out/ramp.exr"));
  EXPECT_TRUE(temporaries_under(s.dir).empty());
}

// A loop through a hard link (another name of the same file) is a loop, not 16 levels of it.
TEST(RecipeChain, LoopsThroughAnyNameAreLoops) {
  Scratch s;
  s.write("a.spectral", R"({"source": "b.spectral"})");
  fs::create_hard_link(s / "a.spectral", s / "b.spectral");
  auto r = sh("oiiotool " + (s / "a.spectral") + " -o " + (s / "o.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("loop"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("a chain of more than"), std::string::npos) << r.err;
}

// A crash still cleans up: with the limit raised (a variable only the tests set) and a small
// stack, the chain overflows the stack; the handler runs on its alternate stack, removes the
// temporaries (the batch's manifest, a --report) and the process dies of SIGSEGV (exit 139).
TEST(RecipeChain, AStackOverflowStillRemovesTheTemporaries) {
#ifdef SPECTRALIZE_SANITIZED
  // AddressSanitizer catches the overflow with its own handler and exits 1: the binary under
  // test is not the one users run, so the signal's path is only checked in normal builds.
  GTEST_SKIP() << "AddressSanitizer handles stack overflows itself";
#endif
  Scratch s;
  const std::string first = make_chain(s, 2000);
  const std::string crash = "ulimit -s 512; SPECTRALIZE_TEST_RECIPE_DEPTH=100000 ";
  auto r = sh(crash + SPECTRALIZE_BINARY + " ingest -q " + first + " -o " + (s / "out"));
  EXPECT_EQ(r.exit_code, 128 + SIGSEGV) << r.err;
  EXPECT_TRUE(temporaries_under(s.dir).empty()) << temporaries_under(s.dir)[0];
  r = sh(crash + SPECTRALIZE_BINARY + " " + first + " -o " + (s / "o.exr") + " --report " +
         (s / "r.json"));
  EXPECT_EQ(r.exit_code, 128 + SIGSEGV) << r.err;
  EXPECT_TRUE(temporaries_under(s.dir).empty()) << temporaries_under(s.dir)[0];
  EXPECT_FALSE(fs::exists(s / "r.json"));
}

}  // namespace
