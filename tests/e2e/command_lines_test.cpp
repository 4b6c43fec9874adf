// Command lines and recipes through the real binary and stock oiiotool (the guide's "Files
// and guarantees", Command lines and recipes): empty values, flags of another command and long
// values are refused with exit 2 in a short message naming the slip; `--`-separated inputs and
// 255-byte output names work and --help gives the real defaults; recipes refuse what the
// command line refuses, naming the recipe, and a recipe over 64 KB is refused with a short
// message.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_support.h"

namespace fs = std::filesystem;
using e2e::run;
using e2e::tool;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_cli") {}
};

struct BadFlag {
  const char* args;
  const char* expected;
};
class CommandLinesBadFlags : public ::testing::TestWithParam<BadFlag> {};

TEST_P(CommandLinesBadFlags, AreRefusedWithExitTwoNamingTheSlip) {
  auto r = run(GetParam().args);
  EXPECT_EQ(r.exit_code, 2) << GetParam().args << "\n" << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 2000u) << "messages do not echo huge values";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CommandLinesBadFlags,
    ::testing::Values(
        BadFlag{"in.exr -o o.exr --threads ''", "--threads: an empty value"},
        BadFlag{"--color 1,1,1 --observer ''", "--observer: an empty value"},
        BadFlag{"--color 1,1,1 --mode ''", "--mode: an empty value"},
        BadFlag{"in.exr -o o.exr --cache ''", "--cache: an empty value"},
        BadFlag{"in.exr -o o.exr --report ''", "--report: an empty file name"},
        BadFlag{"in.exr -o ''", "-o: an empty file name"},
        BadFlag{"--color 1,1,1 --report r.json", "--report does not apply to --color"},
        BadFlag{"--color 1,1,1 --compression zip", "--compression does not apply to --color"},
        BadFlag{"--color 1,1,1 --tile 64", "--tile does not apply"},
        BadFlag{"--to-rgb x.exr -o y.exr --wavelengths 400:700:10", "--wavelengths does not apply"},
        BadFlag{"--color 1 1 1", "--color 1,1,1"},
        // A table's flags that cannot shape it are refused, not ignored.
        BadFlag{"table -o t.spztab --mode reflectance --emission-basis D65",
                "--emission-basis does not shape a reflectance table"},
        BadFlag{"table -o t.spztab --mode emission --illuminant A",
                "--illuminant does not shape an emission table"},
        BadFlag{"table -o t.spztab --mode reflectance --model natural --filter 0.5",
                "--filter does not shape a reflectance table of the natural model"},
        // And every other front end's: --color, an image, ingest (recipes below, Python in
        // tests/python/test_arguments.py).
        BadFlag{"--color 0.5,0.4,0.3 --model natural --filter 0.5",
                "--filter does not shape emission spectra of the natural model; leave it out"},
        BadFlag{"--color 0.5,0.4,0.3 --illuminant A",
                "--illuminant does not shape emission spectra"},
        BadFlag{"--color 0.5,0.4,0.3 --mode reflectance --emission-basis D65 -o p.png",
                "--emission-basis does not shape reflectance spectra"},
        BadFlag{
            SPECTRALIZE_SOURCE_DIR "/testimages/grey_ramp8.png -o o.exr --model smooth "
                                   "--filter 0.5",
            "--filter does not shape the spectra of the smooth model, a light's or a surface's"},
        BadFlag{SPECTRALIZE_SOURCE_DIR "/testimages/grey_ramp8.png -o o.exr --mode emission "
                                       "--illuminant A",
                "--illuminant does not shape emission spectra"},
        BadFlag{"ingest " SPECTRALIZE_SOURCE_DIR "/testimages -o ingested --model exemplar "
                "--curvature 20",
                "--curvature does not shape the spectra of the exemplar model"},
        BadFlag{"in.exr -o o.exr --compression bogus", "--compression: 'bogus'"},
        BadFlag{"--color 1,1,1 --colorspace "
                "ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ"
                "ZZZZZ"
                "ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ"
                "ZZZZZ",
                "bytes)"}));

// What may shape an input's spectra is not refused: a surface's illuminant for an image whose
// mode is decided from the file.
TEST(CommandLines, ASettingThatMayShapeAnInputIsAccepted) {
  Scratch s;
  auto r = run(kImages + "grey_ramp8.png -q -o " + (s / "a.exr") + " --illuminant A");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "a.exr"));
}

TEST(CommandLines, DoubleDashAndLongNamesWork) {
  Scratch s;
  fs::copy_file(kImages + "grey_ramp8.png", s / "-dash.png");
  auto r = run("-q -o " + (s / "a.exr") + " -- -dash.png", "cd " + s.dir.string() + " &&");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / "a.exr"));
  // An output name of 255 bytes (NAME_MAX): the temporary name fits too.
  const std::string name = std::string(251, 'n') + ".exr";
  r = run(kImages + "grey_ramp8.png -q -o " + (s / name));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(s / name));
  // --help gives the real default of --filter.
  r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  const std::regex filter(R"(--filter K[^\[]*\[auto\])");
  EXPECT_TRUE(std::regex_search(r.out, filter)) << r.out.substr(0, 3000);
}

// The reference's generators use --help's names for the commands (the leading "--" optional),
// list them when given another, take nothing else, and are in --help themselves.
TEST(CommandLines, HelpPagesAreNamedAsHelpNamesTheCommands) {
  const e2e::Run help = run("--help");
  ASSERT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--help-markdown-for COMMAND"), std::string::npos);
  // The commands as --help's "Flags by command" names them: each has a page.
  const std::size_t from = help.out.find("Flags by command:\n");
  const std::size_t to = help.out.find("\n\n", from);
  ASSERT_NE(from, std::string::npos);
  std::istringstream section(help.out.substr(from, to - from));
  std::string line;
  std::getline(section, line);
  std::vector<std::string> names;
  while (std::getline(section, line))
    if (line.rfind("  ", 0) == 0 && line[2] != ' ')
      names.push_back(line.substr(2, line.find(' ', 2) - 2));
  EXPECT_EQ(names.size(), 7u) << help.out.substr(from, to - from);
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const e2e::Run page = run("--help-markdown-for " + name);
    EXPECT_EQ(page.exit_code, 0) << page.err;
    EXPECT_EQ(page.out.rfind("| Flag | What it does | Default |", 0), 0u) << page.out;
    if (name.rfind("--", 0) == 0) {
      EXPECT_EQ(run("--help-markdown-for " + name.substr(2)).out, page.out);
    }
  }
  // Another name: exit 2, the valid ones listed.
  const e2e::Run bad = run("--help-markdown-for colour");
  EXPECT_EQ(bad.exit_code, 2);
  for (const std::string& name : names) EXPECT_NE(bad.err.find(name), std::string::npos) << bad.err;
  // Anything else on the line is a slip, not ignored.
  for (const char* extra : {"--help-markdown-for table extra", "--help-markdown-for table -q",
                            "--help-man in.png", "--help-markdown --threads 2"}) {
    SCOPED_TRACE(extra);
    const e2e::Run r = run(extra);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

// A config that cannot be loaded is the job's failure (exit 1) whether --config or $OCIO names
// it, a built-in URI included (docs/guide/files.md, Exit status).
TEST(CommandLines, AConfigThatCannotBeLoadedExitsOneHoweverItIsNamed) {
  for (const char* config : {"ocio://no-such-config", "/nonexistent/config.ocio"}) {
    SCOPED_TRACE(config);
    const e2e::Run flag = run(std::string("--color 1,1,1 --config ") + config);
    const e2e::Run env = run("--color 1,1,1", std::string("OCIO=") + config);
    EXPECT_EQ(flag.exit_code, 1) << flag.err;
    EXPECT_EQ(env.exit_code, 1) << env.err;
    EXPECT_NE(flag.err.find(config), std::string::npos) << flag.err;
    EXPECT_NE(env.err.find(config), std::string::npos) << env.err;
  }
}

// Recipes and the CLI share one schema: the same values are accepted and refused.
TEST(CommandLines, RecipesRefuseWhatTheCliRefuses) {
  Scratch s;
  fs::copy_file(kImages + "grey_ramp8.png", s / "grey.png");
  for (const char* recipe :
       {R"({"source": "grey.png", "compression": "bogus"})", R"({"source": "grey.png", "tile": 7})",
        R"({"source": "grey.png", "threads": ""})", R"({"source": "grey.png", "report": "x"})",
        R"({"source": "grey.png", "model": "natural", "filter": "0.5"})"}) {
    std::ofstream(s / "r.spectral") << recipe;
    auto t = tool("oiiotool " + (s / "r.spectral") + " -o " + (s / "o.exr"));
    EXPECT_NE(t.exit_code, 0) << recipe;
    EXPECT_NE(t.out.find("r.spectral"), std::string::npos) << t.out;
  }
  // A setting that shapes nothing, named as the recipe spells it.
  std::ofstream(s / "r.spectral")
      << R"({"source": "grey.png", "mode": "emission", "illuminant": "A"})";
  auto shaped = tool("oiiotool " + (s / "r.spectral") + " -o " + (s / "o.exr"));
  EXPECT_NE(shaped.exit_code, 0);
  EXPECT_NE(shaped.out.find("illuminant does not shape emission spectra"), std::string::npos)
      << shaped.out;
  // Recipes over 64 KB are refused (docs/guide/files.md), with a short message.
  std::ofstream(s / "big.spectral")
      << "{\"source\": \"grey.png\", \"x\": \"" << std::string(70000, 'y') << "\"}";
  auto t = tool("oiiotool " + (s / "big.spectral") + " -o " + (s / "o.exr"));
  EXPECT_NE(t.exit_code, 0);
  EXPECT_LT(t.out.size(), 2000u);
}

}  // namespace
