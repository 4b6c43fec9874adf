// Safe writes (imagefile/safe_output.h, docs/DESIGN.md §9): an AtomicOutput's data go to an
// exclusive temporary file beside the destination and appear there, complete, only on commit; an
// uncommitted output leaves nothing and removes its temporary; an existing file is replaced
// only on commit; the run's registry refuses inputs, other outputs and their aliases; links
// spectralize did not make, directories and other non-regular files are refused, with messages
// naming the file; streams are written in place; the signal handlers remove temporaries.
// Oracles: the file system itself (stat, readdir, the bytes read back with ifstream or OIIO),
// the temporary name pattern the header states, and errno texts from strerror.

#include "imagefile/safe_output.h"

#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

// "'text'", as the messages quote a path (appended: GCC 12 warns falsely on "'" + std::string).
std::string in_quotes(const std::string& text) {
  std::string out = "'";
  out += text;
  out += "'";
  return out;
}

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("safe_output") {}
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The names in a folder, sorted.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The header's pattern of a temporary file's name, ".<name>.spectralize-XXXXXX.tmp", written
// out independently of the code under test.
bool looks_temporary(const std::string& name, const std::string& destination_name) {
  const std::regex pattern("\\." + std::regex_replace(destination_name, std::regex("\\."), "\\.") +
                           "\\.spectralize-[A-Za-z0-9]{6}\\.tmp");
  return std::regex_match(name, pattern);
}

// The message of the FileError `fn` throws; a test failure if it throws nothing or another type.
std::string file_error(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const FileError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no FileError thrown";
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// --- The temporary file and the commit ---

TEST(SafeOutput, DataGoToAnExclusiveTemporaryBesideTheDestination) {
  TempDir t;
  const std::string dest = t / "image.exr";
  AtomicOutput out(dest);
  EXPECT_EQ(out.destination(), dest);
  EXPECT_EQ(out.kind(), AtomicOutput::Kind::file);
  // In the destination's folder, under the header's name, a regular file of its own (not a
  // link), while nothing is at the destination yet.
  const fs::path tmp(out.path());
  EXPECT_EQ(fs::canonical(tmp.parent_path()), fs::canonical(t.dir));
  EXPECT_TRUE(looks_temporary(tmp.filename().string(), "image.exr")) << tmp;
  EXPECT_TRUE(is_temporary_name(tmp.filename().string()));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(tmp)));
  out.write("abc");
  EXPECT_FALSE(fs::exists(dest));
  EXPECT_EQ(read_all(out.path()), "abc");
}

TEST(SafeOutput, ACommittedOutputAppearsCompleteAtTheDestination) {
  TempDir t;
  const std::string dest = t / "report.json";
  std::string expected;
  {
    AtomicOutput out(dest);
    for (int i = 0; i < 1000; ++i) {
      const std::string chunk = "line " + std::to_string(i) + "\n";
      out.write(chunk);
      expected += chunk;
    }
    EXPECT_FALSE(fs::exists(dest));
    out.commit();
    // Moved, not copied: the temporary is gone at once.
    EXPECT_FALSE(fs::exists(out.path()));
  }
  EXPECT_EQ(read_all(dest), expected);
  // Nothing but the destination is left in the folder.
  EXPECT_EQ(names_in(t.dir), std::vector<std::string>{"report.json"});
}

TEST(SafeOutput, AnUncommittedOutputLeavesNothing) {
  TempDir t;
  const std::string dest = t / "a.exr";
  std::string tmp;
  {
    AtomicOutput out(dest);
    out.write(std::string(100000, 'x'));
    tmp = out.path();
    EXPECT_TRUE(fs::exists(tmp));
  }
  EXPECT_FALSE(fs::exists(dest));
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_TRUE(names_in(t.dir).empty());
}

TEST(SafeOutput, AnExistingFileIsReplacedOnlyOnCommit) {
  TempDir t;
  const std::string dest = t / "a.txt";
  write_file(dest, "old contents");
  {
    AtomicOutput out(dest);
    out.write("new");
    EXPECT_EQ(read_all(dest), "old contents");  // untouched while the output is written
  }
  EXPECT_EQ(read_all(dest), "old contents");  // not committed: still the old file
  {
    AtomicOutput out(dest);
    out.write("new");
    out.commit();
  }
  EXPECT_EQ(read_all(dest), "new");
  EXPECT_EQ(names_in(t.dir), std::vector<std::string>{"a.txt"});
}

TEST(SafeOutput, ACommitOfNothingIsRefusedAndLeavesNothing) {
  TempDir t;
  const std::string dest = t / "empty.png";
  {
    AtomicOutput out(dest);
    const std::string why = file_error([&] { out.commit(); });
    EXPECT_TRUE(contains(why, in_quotes(dest))) << why;
    EXPECT_TRUE(contains(why, "nothing was written")) << why;
  }
  EXPECT_TRUE(names_in(t.dir).empty());
}

TEST(SafeOutput, AFileShorterThanWhatWasWrittenIsNeverCommitted) {
  // A short write that went unnoticed (here: the temporary truncated behind the writer's back)
  // must not become a truncated file at the destination.
  TempDir t;
  const std::string dest = t / "short.exr";
  write_file(dest, "the old file");
  {
    AtomicOutput out(dest);
    out.write("0123456789");
    ASSERT_EQ(::truncate(out.path().c_str(), 4), 0);
    const std::string why = file_error([&] { out.commit(); });
    EXPECT_TRUE(contains(why, in_quotes(dest))) << why;
    EXPECT_TRUE(contains(why, "4 bytes of 10")) << why;
  }
  EXPECT_EQ(read_all(dest), "the old file");
  EXPECT_EQ(names_in(t.dir), std::vector<std::string>{"short.exr"});
}

TEST(SafeOutput, OverwriteReplacesBytesInPlaceAndNeverGrowsTheFile) {
  TempDir t;
  const std::string dest = t / "header.exr";
  {
    AtomicOutput out(dest);
    out.write("count=00000000;end");
    out.overwrite(6, "12345678");
    const std::string why = file_error([&] { out.overwrite(15, "xyzw"); });  // past the end
    EXPECT_TRUE(contains(why, in_quotes(dest))) << why;
    out.commit();
  }
  EXPECT_EQ(read_all(dest), "count=12345678;end");
}

TEST(SafeOutput, OpenImageIOWritesThroughTheCheckedProxy) {
  // A TIFF written through proxy() (libtiff reads back and rewrites its directory), read back
  // by OIIO from the destination: every sample as written.
  TempDir t;
  const std::string dest = t / "through_proxy.tif";
  const int w = 64, h = 48;
  std::vector<unsigned short> px(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<unsigned short>(i * 37 % 65536);
  {
    AtomicOutput out(dest);
    auto writer = OIIO::ImageOutput::create("tiff");
    ASSERT_TRUE(writer);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeUInt16);
    ASSERT_TRUE(writer->set_ioproxy(out.proxy()));
    ASSERT_TRUE(writer->open(dest, spec)) << writer->geterror();
    ASSERT_TRUE(writer->write_image(OIIO::TypeUInt16, px.data()));
    ASSERT_TRUE(writer->close());
    EXPECT_FALSE(fs::exists(dest));
    out.check();
    out.commit();
  }
  auto in = OIIO::ImageInput::open(dest);
  ASSERT_TRUE(in) << OIIO::geterror();
  ASSERT_EQ(in->spec().width, w);
  ASSERT_EQ(in->spec().height, h);
  std::vector<unsigned short> got(px.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeUInt16, got.data()));
  EXPECT_EQ(got, px);
  EXPECT_EQ(names_in(t.dir), std::vector<std::string>{"through_proxy.tif"});
}

TEST(SafeOutput, TheTemporaryNameFitsAFileNameOfTheLongestLength) {
  TempDir t;
  const std::string name = std::string(250, 'n') + ".exr";  // 254 bytes: NAME_MAX is 255
  const std::string dest = t / name;
  {
    AtomicOutput out(dest);
    EXPECT_LE(fs::path(out.path()).filename().string().size(), 255u);
    EXPECT_EQ(fs::path(out.path()).parent_path(), fs::path(dest).parent_path());
    out.write("x");
    out.commit();
  }
  EXPECT_EQ(read_all(dest), "x");
}

TEST(SafeOutput, AUserNamedLinkIsWrittenAtItsTargetAndStaysALink) {
  TempDir t;
  fs::create_directories(t.dir / "real");
  const std::string target = t / "real/a.png";
  const std::string link = t / "link.png";
  fs::create_symlink(target, link);  // to a file not there yet
  {
    AtomicOutput out(link);
    out.write("data");
    out.commit();
  }
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read_all(target), "data");
}

// --- Refusals: messages name the file ---

TEST(SafeOutput, DirectoriesMissingFoldersAndEmptyNamesAreRefused) {
  TempDir t;
  fs::create_directories(t.dir / "sub");
  std::string why = file_error([&] { AtomicOutput out(t / "sub"); });
  EXPECT_TRUE(contains(why, in_quotes((t / "sub")))) << why;
  EXPECT_TRUE(contains(why, "is a directory")) << why;
  why = file_error([&] { AtomicOutput out(t / "no/such/folder/a.exr"); });
  EXPECT_TRUE(contains(why, in_quotes((t / "no/such/folder/a.exr")))) << why;
  EXPECT_TRUE(contains(why, "does not exist")) << why;
  why = file_error([&] { AtomicOutput out(""); });
  EXPECT_TRUE(contains(why, "empty")) << why;
  // A "folder" that is a file.
  write_file(t / "plain", "x");
  why = file_error([&] { AtomicOutput out(t / "plain/a.exr"); });
  EXPECT_TRUE(contains(why, in_quotes((t / "plain/a.exr")))) << why;
  EXPECT_EQ(names_in(t.dir), (std::vector<std::string>{"plain", "sub"}));
}

TEST(SafeOutput, NonRegularFilesAreRefusedUnlessStreamsAreAllowed) {
  TempDir t;
  const std::string fifo = t / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string why = file_error([&] { AtomicOutput out(fifo); });
  EXPECT_TRUE(contains(why, in_quotes(fifo))) << why;
  EXPECT_TRUE(contains(why, "not a regular file")) << why;
  why = file_error([&] { AtomicOutput out("/dev/null"); });
  EXPECT_TRUE(contains(why, "'/dev/null'")) << why;
  why = file_error([&] { AtomicOutput out("/dev/stdout"); });
  EXPECT_TRUE(contains(why, "'/dev/stdout'")) << why;
  EXPECT_TRUE(contains(why, "stream")) << why;
  // Allowed: a pipe is written in place, and is still the pipe when the output ends.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  {
    AtomicOutput out(fifo, WriteRules::named("the list").streams());
    EXPECT_EQ(out.kind(), AtomicOutput::Kind::stream);
    out.write("through the pipe");
    out.commit();
  }
  char buf[64] = {};
  const ssize_t n = ::read(reader, buf, sizeof buf);
  ::close(reader);
  EXPECT_EQ(std::string(buf, n > 0 ? static_cast<std::size_t>(n) : 0), "through the pipe");
  struct stat st = {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(names_in(t.dir), std::vector<std::string>{"pipe"});
  AtomicOutput null_out("/dev/null", WriteRules::named("x").streams());
  EXPECT_EQ(null_out.kind(), AtomicOutput::Kind::stream);
}

TEST(SafeOutput, AFailingWriteThrowsTheSystemsReasonNamingTheDestination) {
  // /dev/full refuses every byte with ENOSPC.
  if (!fs::exists("/dev/full")) {
    GTEST_SKIP() << "no /dev/full";
  }
  AtomicOutput out("/dev/full", WriteRules::named("the report").streams());
  const std::string why = file_error([&] { out.write("abc"); });
  EXPECT_TRUE(contains(why, "'/dev/full'")) << why;
  EXPECT_TRUE(contains(why, std::strerror(ENOSPC))) << why;
  // check() and commit() report it again.
  EXPECT_TRUE(contains(file_error([&] { out.check(); }), std::strerror(ENOSPC)));
  EXPECT_TRUE(contains(file_error([&] { out.commit(); }), std::strerror(ENOSPC)));
}

TEST(SafeOutput, AWritePastTheFileSizeLimitIsAnErrorAndLeavesNothing) {
  TempDir t;
  const std::string dest = t / "big.exr";
  install_cleanup_handlers();  // SIGXFSZ ignored: the write fails with EFBIG instead
  struct rlimit old = {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  std::string why;
  {
    AtomicOutput out(dest);
    struct rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    why = file_error([&] { out.write(std::string(10000, 'x')); });
    ::setrlimit(RLIMIT_FSIZE, &old);
    EXPECT_TRUE(contains(file_error([&] { out.commit(); }), in_quotes(dest)));
  }
  EXPECT_TRUE(contains(why, in_quotes(dest))) << why;
  EXPECT_TRUE(contains(why, std::strerror(EFBIG))) << why;
  EXPECT_TRUE(names_in(t.dir).empty());
}

TEST(SafeOutput, FailGivesTheSystemsReasonWhenOneIsKnown) {
  TempDir t;
  AtomicOutput out(t / "a.tif");
  // A known errno: a FileError with its text.
  try {
    out.fail("TIFF: cannot write", ENOSPC);
    ADD_FAILURE() << "fail() returned";
  } catch (const FileError& e) {
    EXPECT_TRUE(contains(e.what(), "TIFF: cannot write")) << e.what();
    EXPECT_TRUE(contains(e.what(), std::strerror(ENOSPC))) << e.what();
  }
  // No reason known (room on the disk, no size limit): the writer's message as a plain Error.
  struct rlimit lim = {};
  ::getrlimit(RLIMIT_FSIZE, &lim);
  if (lim.rlim_cur != RLIM_INFINITY) {
    GTEST_SKIP() << "a file-size limit is set";
  }
  try {
    out.fail("TIFF: bad strip");
    ADD_FAILURE() << "fail() returned";
  } catch (const FileError& e) {
    ADD_FAILURE() << "a FileError without a reason: " << e.what();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "TIFF: bad strip");
  }
}

// --- The run's registry ---

TEST(SafeOutput, AFileTheRunReadsIsNeverReplacedUnderAnyAlias) {
  TempDir t;
  const std::string input = t / "in.png";
  write_file(input, "input bytes");
  fs::create_directories(t.dir / "sub");
  fs::create_symlink(input, t.dir / "alias.png");
  fs::create_hard_link(input, t.dir / "hard.png");
  ReadFileScope scope;
  protect_input(input, "the input");
  for (const std::string& alias : {input, t / "alias.png", t / "hard.png", t / "sub/../in.png",
                                   (t.dir / "./in.png").string()}) {
    SCOPED_TRACE(alias);
    const std::string why = file_error([&] { AtomicOutput out(alias); });
    EXPECT_TRUE(contains(why, in_quotes(alias))) << why;
    EXPECT_TRUE(contains(why, "the input '" + input + "'")) << why;
  }
  EXPECT_EQ(read_all(input), "input bytes");
}

TEST(SafeOutput, TheInputsGivenToAnOutputAreRefusedToo) {
  TempDir t;
  const std::string input = t / "in.exr";
  write_file(input, "input");
  fs::create_hard_link(input, t.dir / "same.exr");
  const std::vector<std::string> inputs = {input};
  // No ReadFileScope needed: the inputs are given.
  const std::string why = file_error([&] { AtomicOutput out(t / "same.exr", {}, inputs); });
  EXPECT_TRUE(contains(why, in_quotes((t / "same.exr")))) << why;
  EXPECT_TRUE(contains(why, in_quotes(input))) << why;
  EXPECT_EQ(read_all(input), "input");
}

TEST(SafeOutput, TwoOutputsOfARunNeverGoToOneFile) {
  TempDir t;
  ReadFileScope scope;
  const std::string dest = t / "out.exr";
  {
    AtomicOutput first(dest, WriteRules::named("the output of 'a.png'"));
    // The same place, while the first lives, under another spelling.
    const std::string why = file_error([&] { AtomicOutput second(t / "./out.exr"); });
    EXPECT_TRUE(contains(why, in_quotes((t / "./out.exr")))) << why;
    EXPECT_TRUE(contains(why, "the output of 'a.png'")) << why;
    first.write("first");
    first.commit();
  }
  // And after it was committed: the new file is remembered, under its name and its aliases.
  fs::create_hard_link(dest, t.dir / "hard.exr");
  for (const std::string& again : {dest, t / "hard.exr"}) {
    const std::string why = file_error([&] { AtomicOutput second(again); });
    EXPECT_TRUE(contains(why, in_quotes(again))) << why;
  }
  EXPECT_EQ(read_all(dest), "first");
}

TEST(SafeOutput, TheRegistryIsForgottenWhenTheLastScopeEnds) {
  TempDir t;
  const std::string input = t / "in.png";
  write_file(input, "input");
  {
    ReadFileScope outer;
    {
      ReadFileScope inner;  // nested scopes share the registry
      protect_input(input, "the input");
    }
    EXPECT_FALSE(file_error([&] { AtomicOutput out(input); }).empty());
  }
  // No scope: nothing is protected, and an input protected now is not kept either.
  protect_input(input, "the input");
  AtomicOutput out(input);
  out.write("replaced");
  out.commit();
  EXPECT_EQ(read_all(input), "replaced");
}

TEST(SafeOutput, CheckReadableFileRefusesWhatCannotBeReadAndProtectsWhatIsRead) {
  TempDir t;
  std::string why = file_error([&] { check_readable_file(t / "missing.png", "input"); });
  EXPECT_TRUE(contains(why, in_quotes((t / "missing.png")))) << why;
  EXPECT_TRUE(contains(why, "no such file")) << why;
  why = file_error([&] { check_readable_file(t.dir.string(), "input"); });
  EXPECT_TRUE(contains(why, "is a directory")) << why;
  const std::string fifo = t / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  why = file_error([&] { check_readable_file(fifo, "--config"); });  // refused, never blocks
  EXPECT_TRUE(contains(why, in_quotes(fifo))) << why;
  EXPECT_TRUE(contains(why, "--config")) << why;
  EXPECT_TRUE(contains(why, "a pipe")) << why;
  const std::string input = t / "in.exr";
  write_file(input, "x");
  ReadFileScope scope;
  check_readable_file(input, "input");
  EXPECT_TRUE(contains(file_error([&] { AtomicOutput out(input); }), in_quotes(input)));
}

TEST(SafeOutput, LinksTheToolDidNotMakeBelowItsFolderAreRefused) {
  TempDir t;
  const std::string below = t / "library";
  fs::create_directories(below + "/real");
  fs::create_directories(t.dir / "elsewhere");
  fs::create_symlink(t.dir / "elsewhere", below + "/linked_folder");
  fs::create_symlink(t.dir / "elsewhere/x.exr", below + "/linked.exr");
  const WriteRules rules = WriteRules::named("the ingest output").below(below);
  std::string why = file_error([&] { AtomicOutput out(below + "/linked.exr", rules); });
  EXPECT_TRUE(contains(why, in_quotes(below + "/linked.exr"))) << why;
  EXPECT_TRUE(contains(why, "symbolic link")) << why;
  why = file_error([&] { AtomicOutput out(below + "/linked_folder/a.exr", rules); });
  EXPECT_TRUE(contains(why, in_quotes(below + "/linked_folder"))) << why;
  EXPECT_TRUE(contains(why, "symbolic link")) << why;
  why = file_error([&] { AtomicOutput out(t / "elsewhere/b.exr", rules); });
  EXPECT_TRUE(contains(why, "not inside")) << why;
  EXPECT_TRUE(fs::is_empty(t.dir / "elsewhere"));
  // A real folder below is fine.
  AtomicOutput ok(below + "/real/c.exr", rules);
  ok.write("c");
  ok.commit();
  EXPECT_EQ(read_all(below + "/real/c.exr"), "c");
}

TEST(SafeOutput, AFilePlanRefusesAConflictingPlanUpFront) {
  TempDir t;
  const std::string input = t / "in.png";
  write_file(input, "input");
  fs::create_symlink(input, t.dir / "alias.png");
  FilePlan plan;
  EXPECT_TRUE(plan.read(input, "the input"));
  EXPECT_FALSE(plan.read(t / "alias.png", "the same input again"));
  EXPECT_TRUE(plan.read(t / "missing.png", "a missing input"));  // ignored: fails when read
  EXPECT_EQ(plan.write(t / "a.exr", "the output of 'in.png'"), "");
  std::string why = plan.write(t / "alias.png", "the output of 'x.png'");
  EXPECT_TRUE(contains(why, in_quotes((t / "alias.png")))) << why;
  EXPECT_TRUE(contains(why, "the input")) << why;
  why = plan.write(t / "./a.exr", "the output of 'y.png'");
  EXPECT_TRUE(contains(why, in_quotes((t / "./a.exr")))) << why;
  EXPECT_TRUE(contains(why, "the output of 'in.png'")) << why;
  // A planned output's folder may not exist yet.
  EXPECT_EQ(plan.write(t / "later/b.exr", "the output of 'b.png'"), "");
  // Claimed: the run's outputs are checked against the whole plan.
  ReadFileScope scope;
  plan.claim();
  EXPECT_TRUE(contains(file_error([&] { AtomicOutput out(input); }), in_quotes(input)));
  why = file_error([&] { AtomicOutput out(t / "./a.exr"); });
  EXPECT_TRUE(contains(why, "the output of 'in.png'")) << why;
  // The planned output itself, as planned, is written.
  AtomicOutput out(t / "a.exr");
  out.write("a");
  out.commit();
  EXPECT_EQ(read_all(t / "a.exr"), "a");
}

// --- Places, names, stale temporaries ---

TEST(SafeOutput, EveryAliasOfAFileHasOnePlace) {
  TempDir t;
  const std::string file = t / "f.exr";
  write_file(file, "f");
  fs::create_directories(t.dir / "sub");
  fs::create_symlink(file, t.dir / "link.exr");
  fs::create_hard_link(file, t.dir / "hard.exr");
  struct stat st = {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  const FilePlace expected{static_cast<std::uint64_t>(st.st_dev),
                           static_cast<std::uint64_t>(st.st_ino), ""};
  for (const std::string& alias : {file, t / "link.exr", t / "hard.exr", t / "sub/../f.exr"}) {
    EXPECT_EQ(file_place(alias), expected) << alias;
  }
  const int fd = ::open(file.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  EXPECT_EQ(file_place("/proc/self/fd/" + std::to_string(fd)), expected);
  ::close(fd);
  // Not there yet: the nearest existing folder and the rest of the path, for every spelling,
  // also through a link to a file that does not exist.
  ASSERT_EQ(::stat(t.dir.c_str(), &st), 0);
  const FilePlace missing{static_cast<std::uint64_t>(st.st_dev),
                          static_cast<std::uint64_t>(st.st_ino), "new/a.exr"};
  fs::create_symlink(t.dir / "new/a.exr", t.dir / "dangling.exr");
  for (const std::string& alias : {t / "new/a.exr", t / "sub/../new/a.exr", t / "dangling.exr"}) {
    EXPECT_EQ(file_place(alias), missing) << alias;
  }
  EXPECT_NE(file_place(t / "new/b.exr"), missing);
}

TEST(SafeOutput, LinkTargetFollowsLinksToFilesNotThereYet) {
  TempDir t;
  fs::create_directories(t.dir / "real");
  fs::create_symlink("real/x.exr", t.dir / "rel.exr");  // relative to the link's folder
  fs::create_symlink(t.dir / "rel.exr", t.dir / "chain.exr");
  const fs::path expected = fs::canonical(t.dir) / "real/x.exr";
  EXPECT_EQ(fs::path(link_target(t / "rel.exr")), expected);
  EXPECT_EQ(fs::path(link_target(t / "chain.exr")), expected);
  EXPECT_TRUE(fs::path(link_target("relative/name.exr")).is_absolute());
}

TEST(SafeOutput, TemporaryNamesAreRecognisedByTheirPattern) {
  EXPECT_TRUE(is_temporary_name(".a.exr.spectralize-Ab3xY9.tmp"));
  EXPECT_TRUE(is_temporary_name(".x.spectralize-000000.tmp"));
  EXPECT_FALSE(is_temporary_name("a.exr.spectralize-Ab3xY9.tmp"));    // no leading dot
  EXPECT_FALSE(is_temporary_name(".a.exr.spectralize-Ab3xY.tmp"));    // five X's
  EXPECT_FALSE(is_temporary_name(".a.exr.spectralize-Ab3xY9.tmp~"));  // not the end
  EXPECT_FALSE(is_temporary_name(".a.exr.spectralize-Ab.xY9.tmp"));
  EXPECT_FALSE(is_temporary_name(".spectralize-Ab3xY9.tmp"));  // no name
  EXPECT_FALSE(is_temporary_name("a.exr"));
}

TEST(SafeOutput, StaleTemporariesAreRemovedButLiveOnesKept) {
  TempDir t;
  write_file(t / ".a.exr.spectralize-abc123.tmp", "killed writer");
  write_file(t / ".b.exr.spectralize-ZZZZZZ.tmp", "killed writer");
  write_file(t / ".c.exr.spectralize-abc12.tmp", "not a temporary name");
  write_file(t / "d.exr", "an output");
  fs::create_directories(t.dir / "sub");
  write_file(t / "sub/.e.exr.spectralize-abc123.tmp", "in a subfolder: not swept");
  AtomicOutput live(t / "live.exr");
  live.write("live");
  EXPECT_EQ(remove_stale_temporaries(t.dir.string()), 2u);
  EXPECT_EQ(names_in(t.dir),
            (std::vector<std::string>{".c.exr.spectralize-abc12.tmp",
                                      fs::path(live.path()).filename().string(), "d.exr", "sub"}));
  EXPECT_TRUE(fs::exists(t / "sub/.e.exr.spectralize-abc123.tmp"));
  live.commit();
  EXPECT_EQ(read_all(t / "live.exr"), "live");
}

// --- Signals ---

// Runs `body` in a child process and returns its wait status.
int in_child(const std::function<void()>& body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST(SafeOutput, ASignalRemovesTheTemporariesAndTheProcessDiesOfIt) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    SCOPED_TRACE(strsignal(sig));
    TempDir t;
    const int status = in_child([&] {
      AtomicOutput a(t / "a.exr");
      AtomicOutput b(t / "b.exr");
      a.write("half-written");
      ::raise(sig);
      ::_exit(3);  // not reached when the signal kills the process
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_TRUE(names_in(t.dir).empty());
  }
}

TEST(SafeOutput, AScratchFileIsMadeExclusivelyAndGoesWithItsScopeOrASignal) {
  TempDir t;
  {
    ScratchFile a(t.dir.string(), "list-", ".jsonl");
    ScratchFile b(t.dir.string(), "list-", ".jsonl");
    EXPECT_NE(a.path(), b.path());
    EXPECT_TRUE(std::regex_match(fs::path(a.path()).filename().string(),
                                 std::regex(R"(list-[A-Za-z0-9]{6}\.jsonl)")))
        << a.path();
    EXPECT_EQ(fs::file_size(a.path()), 0u);
    EXPECT_EQ(names_in(t.dir).size(), 2u);
  }
  EXPECT_TRUE(names_in(t.dir).empty());
  const int status = in_child([&] {
    ScratchFile c(t.dir.string(), "list-", ".jsonl");
    write_file(c.path(), "written by another process");
    ::raise(SIGTERM);
    ::_exit(3);
  });
  ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
  EXPECT_TRUE(names_in(t.dir).empty());
  EXPECT_THROW(ScratchFile(t.dir.string() + "/no-such-folder", "x", ""), FileError);
}

TEST(SafeOutput, OnlySigkillLeavesATemporaryAndTheNextSweepRemovesIt) {
  TempDir t;
  const int status = in_child([&] {
    AtomicOutput a(t / "a.exr");
    a.write("half-written");
    ::raise(SIGKILL);
  });
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGKILL);
  const auto left = names_in(t.dir);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_TRUE(looks_temporary(left[0], "a.exr")) << left[0];
  EXPECT_EQ(remove_stale_temporaries(t.dir.string()), 1u);  // its lock died with it
  EXPECT_TRUE(names_in(t.dir).empty());
}

}  // namespace
}  // namespace spectralize
