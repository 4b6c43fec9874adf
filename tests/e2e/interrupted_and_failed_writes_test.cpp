// Writes that fail or are interrupted, through the real binary (the guide's "Files and guarantees"
// (docs/guide/files.md), Outputs are complete or absent, Interruptions): a file-size limit, a full
// disk (a small tmpfs where this machine allows mounting one), /dev/full, a place that cannot be
// written and standard output that cannot be written exit 1 naming the file; every signal whose
// default action ends the process, sent during a long write, removes the temporary file and ends
// the process with that signal; SIGKILL leaves only a recognisable temporary. The oracle is the
// file system: what is left at the destination and beside it.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using e2e::temporaries;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_writes") {}
};

// A float RGB map big enough that converting it takes about a second (written once per run).
std::string big_input(const Scratch& s) {
  const std::string path = s / "big.exr";
  const int w = 2048, h = 1024;
  std::vector<float> px(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = &px[(static_cast<std::size_t>(y) * w + x) * 3];
      p[0] = 0.1f + 2.0f * x / w;
      p[1] = 0.2f + 1.0f * y / h;
      p[2] = 0.3f + 0.5f * ((x ^ y) & 255) / 255.0f;
    }
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeFloat);
  auto out = OIIO::ImageOutput::create(path);
  out->open(path, spec);
  out->write_image(OIIO::TypeFloat, px.data());
  out->close();
  return path;
}

// Starts spectralize with `args` (no shell), returns its pid.
pid_t spawn(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string bin = SPECTRALIZE_BINARY;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    ::execv(SPECTRALIZE_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

// Writes that fail: past a file-size limit (part-way), and into a place that cannot be written.
TEST(FailedWrites, FailingWritesLeaveNothingBehind) {
  Scratch s;
  fs::copy_file(kImages + "hdri_sunset_256x128.exr", s / "in.exr");
  auto r = run("-q " + (s / "in.exr") + " -o " + (s / "out.exr"), "ulimit -f 2000;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("out.exr"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("write failed"), std::string::npos) << r.err;
  EXPECT_EQ(s.files(), std::vector<std::string>{"in.exr"});  // no partial or temporary file
  r = run((s / "in.exr") + " -o /proc/self/out.exr");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/proc/self/out.exr"), std::string::npos) << r.err;
  EXPECT_EQ(fs::file_size(s / "in.exr"), fs::file_size(kImages + "hdri_sunset_256x128.exr"));
}

// Truth: a write that cannot complete (file-size limit just below the file's size, /dev/full)
// exits 1 naming the file and leaves nothing at the destination, for every kind of output.
TEST(FailedWrites, FailedWritesAreFailuresForEveryOutput) {
  Scratch s;
  const std::string in = kImages + "hdri_sunset_256x128.exr";
  ASSERT_EQ(run(in + " -o " + (s / "full.exr") + " -q").exit_code, 0);
  const auto size = fs::file_size(s / "full.exr");
  fs::remove(s / "full.exr");
  // ulimit -f counts 1024-byte blocks: one block short of the whole file.
  const std::string limit = "ulimit -f " + std::to_string(size / 1024 - 1) + ";";
  for (const std::string& args :
       {in + " -o " + (s / "out.exr"), in + " -o " + (s / "out.exr") + " --format float",
        in + " -o " + (s / "out.exr") + " --tile 32"}) {
    auto r = run("-q " + args, limit);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("out.exr"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s / "out.exr")) << args;
  }
  ASSERT_EQ(run(in + " -o " + (s / "spec.exr") + " -q").exit_code, 0);
  auto r = run("--to-rgb " + (s / "spec.exr") + " -o " + (s / "rgb.exr") + " -q", "ulimit -f 8;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "rgb.exr"));
  r = run("--color 0.2,0.5,0.1 -o " + (s / "plot.png"), "ulimit -f 8;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("plot.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "plot.png"));
  // Standard output that cannot be written.
  const std::string err = s / "err.txt";
  const int status =
      std::system((std::string(SPECTRALIZE_BINARY) + " --color 1,1,1 >/dev/full 2>" + err).c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
  EXPECT_NE(e2e::slurp(err).find("standard output"), std::string::npos) << e2e::slurp(err);
  fs::remove(err);
  r = run("--color 1,1,1 -o /dev/full");
  EXPECT_EQ(r.exit_code, 1);
  r = run(in + " -o " + (s / "x.exr") + " -q --report /dev/full");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
  // Only the image written before the report failed... and nothing else.
  for (const auto& name : s.files()) {
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
  }
}

// A full disk: a 1 MB tmpfs where mounting is allowed (root with CAP_SYS_ADMIN); the write
// fails, names the file, and leaves nothing on the full file system.
TEST(FailedWrites, FullDiskLeavesNothing) {
  Scratch s;
  const std::string mnt = s / "small";
  fs::create_directory(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                 << "); the ulimit -f tests cover failing writes";
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
  } unmount{mnt};
  for (const std::string& args : {kImages + "hdri_sunset_256x128.exr -o " + mnt + "/out.exr",
                                  "--color 0.2,0.5,0.1 --color 0.1,0.1,0.9 -o " + mnt + "/p.tif"}) {
    // Fill the disk but for a few KB first.
    std::ofstream(mnt + "/filler") << std::string(1000 * 1024, 'x') << std::flush;
    auto r = run("-q " + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(mnt), std::string::npos) << r.err;
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(mnt)) left.push_back(e.path().filename());
    EXPECT_EQ(left, std::vector<std::string>{"filler"});
    fs::remove(mnt + "/filler");
  }
}

// Signals sent while the output is being written: the temporary file is removed and the
// process dies of the signal (shells report 128 + signal); nothing at the destination.
class InterruptedWritesBySignalSlow : public ::testing::TestWithParam<int> {};

TEST_P(InterruptedWritesBySignalSlow, RemoveTheTemporaryFileAndDieOfTheSignal) {
  Scratch s;
  const std::string in = big_input(s);
  const pid_t pid = spawn({in, "-o", s / "out.exr", "-q", "--threads", "1"});
  // Wait until the temporary file exists and has data in it (the write is under way).
  const auto t0 = std::chrono::steady_clock::now();
  bool writing = false;
  while (!writing && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30)) {
    for (const auto& name : temporaries(s)) writing = writing || fs::file_size(s / name) > 0;
    if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(writing) << "the run never started writing";
  ASSERT_EQ(::kill(pid, GetParam()), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), GetParam());
  EXPECT_TRUE(temporaries(s).empty()) << temporaries(s)[0];
  EXPECT_FALSE(fs::exists(s / "out.exr"));
}

// Every signal whose default action ends the process, crashes included.
INSTANTIATE_TEST_SUITE_P(Cases, InterruptedWritesBySignalSlow,
                         ::testing::Values(SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2,
                                           SIGALRM, SIGXCPU, SIGABRT, SIGSEGV),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(sigabbrev_np(info.param));
                         });

// SIGKILL cannot be caught: it may leave a temporary file, recognisable by its name, and
// never a partial file at the destination; a rerun completes.
TEST(InterruptedWritesSlow, SigkillLeavesOnlyARecognisableTemporary) {
  Scratch s;
  const std::string in = big_input(s);
  const pid_t pid = spawn({in, "-o", s / "out.exr", "-q", "--threads", "1"});
  const auto t0 = std::chrono::steady_clock::now();
  while (temporaries(s).empty() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_FALSE(temporaries(s).empty());
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_FALSE(fs::exists(s / "out.exr"));
  EXPECT_EQ(temporaries(s).size(), 1u);
  auto r = run(in + " -o " + (s / "out.exr") + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "out.exr"));
  EXPECT_EQ(temporaries(s).size(), 1u) << "the rerun leaves no temporary of its own";
}

}  // namespace
