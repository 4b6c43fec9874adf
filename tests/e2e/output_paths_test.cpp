// Where outputs go, through the real binary (the guide's "Files and guarantees"
// (docs/guide/files.md), No file of a run replaces another): a report never replaces an input, the
// output, the OCIO config, a link's target that is one of them or a device, fails before any work
// in a missing folder, and /dev/stdout, /dev/null, FIFOs and symbolic links work as they should; a
// link planted at a temporary file's name is not followed; directories, FIFOs and devices named as
// outputs are never replaced, and two runs to one destination leave one complete file. The oracles
// are the file system (bytes, file types, links) and OIIO reading the outputs.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::read_json;
using e2e::run;
using e2e::temporaries;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_paths") {}
};

// Truth: the report never replaces an input, the output, a symlink or a device, fails before
// any work in a missing folder, and /dev/stdout, /dev/null and pipes work as streams.
TEST(OutputPaths, ReportPathIsCheckedBeforeAnyWork) {
  Scratch s;
  fs::copy_file(kImages + "hdri_forest_256x128.exr", s / "one.exr");
  const std::string original = e2e::slurp(s / "one.exr");
  fs::create_symlink("one.exr", s / "alias.json");
  for (const std::string& report :
       {s / "one.exr", s / "alias.json", s.dir.string() + "/./one.exr"}) {
    auto r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + report);
    EXPECT_EQ(r.exit_code, 1) << report << ": " << r.err;
    EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
    EXPECT_EQ(e2e::slurp(s / "one.exr"), original);
    EXPECT_FALSE(fs::exists(s / "out.exr"));
  }
  auto r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + (s / "out.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "out.exr"));
  r = run((s / "one.exr") + " -o " + (s / "out.exr") + " --report " + (s / "no/dir/r.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no/dir/r.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "out.exr")) << "the image must not be written first";
  // Streams.
  r = run((s / "one.exr") + " -o " + (s / "a.exr") + " -q --report /dev/stdout");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Json::parse(r.out)["pixels"], 32768);
  r = run((s / "one.exr") + " -o " + (s / "b.exr") + " -q --report /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(::mkfifo((s / "fifo.json").c_str(), 0600), 0);
  const std::string cmd = "cat " + (s / "fifo.json") + " > " + (s / "fifo.out") + " & " +
                          SPECTRALIZE_BINARY + " " + (s / "one.exr") + " -o " + (s / "c.exr") +
                          " -q --report " + (s / "fifo.json") + "; wait";
  ASSERT_EQ(std::system(("sh -c '" + cmd + "'").c_str()), 0);
  EXPECT_EQ(read_json(s / "fifo.out")["pixels"], 32768);
  EXPECT_EQ(fs::status(s / "fifo.json").type(), fs::file_type::fifo);  // not replaced
  // Links not yet pointing at a file: a report linked to the output, an output linked to the
  // report; and files the run reads besides the input (its OCIO config, given or by $OCIO).
  fs::create_symlink("e.exr", s / "to_output.json");
  r = run((s / "one.exr") + " -o " + (s / "e.exr") + " -q --report " + (s / "to_output.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "e.exr"));
  fs::create_symlink("f.json", s / "to_report.exr");
  r = run((s / "one.exr") + " -o " + (s / "to_report.exr") + " -q --report " + (s / "f.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(fs::exists(s / "f.json"));
  fs::copy_file(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio", s / "cfg.ocio");
  const std::string config = e2e::slurp(s / "cfg.ocio");
  fs::copy_file(s / "cfg.ocio", s / "cfg.exr");  // OCIO reads a config by any name
  for (const std::string cfg : {"cfg.ocio", "cfg.exr"}) {
    const std::string args =
        cfg == "cfg.ocio" ? " -o " + (s / "g.exr") + " --report " + (s / cfg) : " -o " + (s / cfg);
    r = run((s / "one.exr") + " -q --config " + (s / cfg) + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("reads"), std::string::npos) << r.err;
    EXPECT_EQ(e2e::slurp(s / cfg), config);
    EXPECT_FALSE(fs::exists(s / "g.exr"));
  }
  r = run((s / "one.exr") + " -q -o " + (s / "h.exr") + " --report " + (s / "cfg.ocio"),
          "OCIO=" + (s / "cfg.ocio"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(e2e::slurp(s / "cfg.ocio"), config);
  // A report that cannot be written (a full device) fails the run, and the image is not left.
  for (const char* flag : {"", "--to-rgb"}) {
    const std::string in = *flag ? (s / "a.exr") : (s / "one.exr");
    r = run(std::string(flag) + " " + in + " -o " + (s / "i.exr") + " -q --report /dev/full");
    EXPECT_EQ(r.exit_code, 1) << flag << r.err;
    EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s / "i.exr")) << flag;
  }
  // A symlink to a report is written through: the link stays a link.
  fs::create_symlink("target.json", s / "link.json");
  r = run((s / "one.exr") + " -o " + (s / "d.exr") + " -q --report " + (s / "link.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(s / "link.json"));
  EXPECT_EQ(read_json(s / "target.json")["pixels"], 32768);
}

// The old predictable temporary name (".<name>.spectralize-<pid>.tmp.exr"), planted as a link
// to the input before the process starts: it is not followed, the input is untouched.
TEST(OutputPaths, PlantedLinkAtTheTemporaryNameIsNotFollowed) {
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
TEST(OutputPaths, NonRegularOutputsAreNeverReplaced) {
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
