// Fault injection through the real binary: signals during a long write, a full disk (a small
// tmpfs where this machine allows mounting one; `ulimit -f` always), a link planted at the old
// predictable temporary name, and outputs that are not regular files. The oracle is the file
// system: what is left at the destination and beside it, and the inputs' bytes.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using e2e::temporaries;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_fault") {}
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

// Signals sent while the output is being written: the temporary file is removed and the
// process dies of the signal (shells report 128 + signal); nothing at the destination.
class FaultSignalsSlow : public ::testing::TestWithParam<int> {};

TEST_P(FaultSignalsSlow, RemoveTheTemporaryFileAndDieOfTheSignal) {
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
INSTANTIATE_TEST_SUITE_P(Cases, FaultSignalsSlow,
                         ::testing::Values(SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2,
                                           SIGALRM, SIGXCPU, SIGABRT, SIGSEGV),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(sigabbrev_np(info.param));
                         });

// SIGKILL cannot be caught: it may leave a temporary file, recognisable by its name, and
// never a partial file at the destination; a rerun completes.
TEST(FaultInjectionSlow, SigkillLeavesOnlyARecognisableTemporary) {
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

// A full disk: a 1 MB tmpfs where mounting is allowed (root with CAP_SYS_ADMIN); the write
// fails, names the file, and leaves nothing on the full file system.
TEST(FaultInjection, FullDiskLeavesNothing) {
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
    { std::ofstream(mnt + "/filler") << std::string(1000 * 1024, 'x'); }
    auto r = run("-q " + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(mnt), std::string::npos) << r.err;
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(mnt)) left.push_back(e.path().filename());
    EXPECT_EQ(left, std::vector<std::string>{"filler"});
    fs::remove(mnt + "/filler");
  }
}

// The old predictable temporary name (".<name>.spectralize-<pid>.tmp.exr"), planted as a link
// to the input before the process starts: it is not followed, the input is untouched.
TEST(FaultInjection, PlantedLinkAtTheTemporaryNameIsNotFollowed) {
  Scratch s;
  fs::copy_file(kImages + "hdri_forest_256x128.exr", s / "victim.exr");
  const std::string original = e2e::slurp(s / "victim.exr");
  int gate[2];
  ASSERT_EQ(::pipe(gate), 0);
  const pid_t pid = fork();
  if (pid == 0) {
    char c;
    ::close(gate[1]);
    if (::read(gate[0], &c, 1) != 1) _exit(126);  // wait for the parent's links
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    const std::string in = kImages + "grey_ramp8.png", out = s / "out.exr";
    ::execl(SPECTRALIZE_BINARY, SPECTRALIZE_BINARY, in.c_str(), "-o", out.c_str(), "-q",
            static_cast<char*>(nullptr));
    _exit(127);
  }
  ::close(gate[0]);
  const std::string pid_text = std::to_string(pid);
  for (const std::string& name : {".out.exr.spectralize-" + pid_text + ".tmp.exr",
                                  ".out.exr.spectralize-" + pid_text + ".tmp"})
    fs::create_symlink(s / "victim.exr", s / name);
  ASSERT_EQ(::write(gate[1], "go", 1), 1);
  ::close(gate[1]);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(e2e::slurp(s / "victim.exr"), original);
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(s / "out.exr")));
}

// Outputs that are not regular files are never replaced; two runs to one destination at once
// use different temporary files and one complete file wins.
TEST(FaultInjection, NonRegularOutputsAreNeverReplaced) {
  Scratch s;
  const std::string in = kImages + "grey_ramp8.png";
  fs::create_directory(s / "dir.exr");
  ASSERT_EQ(::mkfifo((s / "fifo.exr").c_str(), 0600), 0);
  for (const std::string& out : {s / "dir.exr", s / "fifo.exr", std::string("/dev/null")}) {
    auto r = run(in + " -o " + out, "timeout 20");
    EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << out << ": " << r.err;
    EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_directory(s / "dir.exr"));
  EXPECT_EQ(fs::status(s / "fifo.exr").type(), fs::file_type::fifo);
  const std::string bin = SPECTRALIZE_BINARY;
  const std::string cmd = bin + " " + in + " -q -o " + (s / "same.exr") + " & " + bin + " " + in +
                          " -q -o " + (s / "same.exr") + " & wait";
  ASSERT_EQ(std::system(("sh -c '" + cmd + "'").c_str()), 0);
  EXPECT_EQ(e2e::read_exr(s / "same.exr").width, 64);
  EXPECT_TRUE(temporaries(s).empty());
}

}  // namespace
