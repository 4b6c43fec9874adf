// spectralize: RGB colours and images to exact spectra (see README.md).

#include <OpenImageIO/argparse.h>
#include <OpenImageIO/oiioversion.h>
#include <fmt/core.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "colour/colour_space.h"
#include "imagefile/openexr_compat.h"
#include "imagefile/safe_output.h"
#include "plot/spectrum_plot.h"
#include "spectralize/core/error.h"
#include "spectralize/version.h"
#include "text/strings.h"
#include "tool/flags.h"
#include "tool/options.h"

using namespace spectralize;
using namespace spectralize::tool;

namespace {

// Flags that are not settings: what to do and where to write. Each lists its commands.
struct CommandFlag {
  const char* flag;
  const char* metavar;
  unsigned commands;
  const char* help;
};
constexpr unsigned kPlots = kPlotColor | kPlotPixel;
constexpr CommandFlag kCommandFlags[] = {
    {"-o", "FILE", kImage | kToRgb | kColor | kPlots | kIngest | kTable,
     "The file to write: the spectral OpenEXR (images), the RGB image (--to-rgb), a plot "
     "(.png, .svg, ...), the printed spectra (--color: .csv, .json), the folder ingest "
     "writes into, or the table (NAME.spztab)"},
    {"--inputs-from", "FILE", kIngest,
     "ingest: a list of inputs, one per line: a path, or a JSON object with \"input\" and any "
     "single-file setting for it"},
    {"--manifest", "FILE", kIngest,
     "ingest: the JSON Lines record of what happened (default: DESTDIR/spectralize-ingest.jsonl, "
     "or a part per shard)"},
    {"--shard", "I/N", kIngest,
     "ingest: do shard I (0-based) of N of the batch (default from SLURM_ARRAY_TASK_ID and "
     "SLURM_ARRAY_TASK_COUNT when set)"},
    {"--to-rgb", "FILE", kToRgb,
     "Integrate a spectral OpenEXR (S0 or T channels, any writer's) back to RGB(A)"},
    {"--color", "R,G,B", kColor | kPlotColor,
     "Spectralize a colour (repeatable); prints CSV or JSON, or plots with -o PLOT.png"},
    {"--plot-pixel", "X,Y", kPlotPixel,
     "Plot the spectrum of pixel X,Y (0-based, top-left) of a spectral EXR (repeatable)"},
    {"--report", "FILE", kImage | kToRgb,
     "Write a JSON report (colour space and why, counts by kind, errors, cache, timings); "
     "/dev/stdout works"},
};

std::string command_name(Command c) {
  switch (c) {
    case kImage:
      return "an image conversion (INPUT -o OUTPUT.exr)";
    case kToRgb:
      return "--to-rgb";
    case kColor:
      return "--color";
    case kPlotColor:
      return "a --color plot";
    case kPlotPixel:
      return "--plot-pixel";
    case kIngest:
      return "ingest";
    case kTable:
      return "table";
  }
  return "this command";
}

std::string commands_list(unsigned commands) {
  std::string out;
  const std::pair<unsigned, const char*> names[] = {
      {kImage, "image"},     {kToRgb, "--to-rgb"},         {kColor, "--color"},
      {kPlotColor, "plots"}, {kPlotPixel, "--plot-pixel"}, {kIngest, "ingest"},
      {kTable, "table"}};
  for (const auto& [bit, name] : names)
    if ((commands & bit) && !(bit == kPlotColor && (commands & kColor)))
      out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

int terminal_width() {
  struct winsize w = {};
  if (::isatty(STDOUT_FILENO) && ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col >= 40)
    return w.ws_col;
  return 100;
}

// "  --flag VALUE   text..." with the text wrapped at the terminal's width.
void print_entry(const std::string& left, const std::string& text, int width) {
  constexpr std::size_t kColumn = 26;
  std::string line = "  " + left;
  line += line.size() + 1 < kColumn ? std::string(kColumn - line.size(), ' ')
                                    : "\n" + std::string(kColumn, ' ');
  std::size_t col = line.size() - line.rfind('\n') - 1;
  if (line.rfind('\n') == std::string::npos) col = line.size();
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find(' ', pos);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(pos, end - pos);
    if (col + word.size() + 1 > static_cast<std::size_t>(width) && col > kColumn) {
      line += "\n" + std::string(kColumn, ' ');
      col = kColumn;
    } else if (col > kColumn) {
      line += ' ';
      ++col;
    }
    line += word;
    col += word.size();
    pos = end + 1;
  }
  fmt::print("{}\n", line);
}

void print_help() {
  const int width = terminal_width();
  fmt::print(
      "spectralize " SPECTRALIZE_VERSION
      " -- exact RGB-to-spectrum conversion (Zhdanov & Potemin)\n"
      "Every spectrum reproduces its input colour exactly, is non-negative, and a reflectance "
      "stays <= 1.\n\n"
      "Usage:\n"
      "  spectralize INPUT -o OUTPUT.exr [options]             an RGB image to a spectral "
      "OpenEXR\n"
      "  spectralize --to-rgb IN.exr -o OUT.exr [options]      a spectral OpenEXR to RGB(A)\n"
      "  spectralize --color R,G,B [--color ...] [options]     spectra of colours (CSV, JSON)\n"
      "  spectralize --color R,G,B [...] -o PLOT.png|PLOT.svg  a plot of their spectra\n"
      "  spectralize --plot-pixel X,Y IN.exr -o PLOT.png       a plot of a pixel of a "
      "spectral EXR\n"
      "  spectralize ingest SRC... -o DESTDIR [options]        a texture library (files, folders,\n"
      "                                                        globs) to spectral OpenEXR\n"
      "  spectralize table -o NAME.spztab [options]            a render-time table of exact\n"
      "                                                        spectra (spectralize/rt.h)\n\n"
      "Flags by command:\n");
  const std::pair<unsigned, const char*> groups[] = {
      {kImage, "image"},     {kToRgb, "--to-rgb"},         {kColor, "--color"},
      {kPlotColor, "plots"}, {kPlotPixel, "--plot-pixel"}, {kIngest, "ingest"},
      {kTable, "table"}};
  for (const auto& [command, name] : groups) {
    std::string flags;
    for (const CommandFlag& f : kCommandFlags)
      if (f.commands & command) flags += std::string(flags.empty() ? "" : " ") + f.flag;
    for (const SettingSpec& spec : settings_schema())
      if (spec.applies(static_cast<Command>(command)) && flags.find(spec.flag) == std::string::npos)
        flags.append(" ").append(spec.flag);
    print_entry(name, flags + " -v -q", width);
  }
  fmt::print("\nCommands and outputs:\n");
  for (const CommandFlag& f : kCommandFlags)
    print_entry(std::string(f.flag) + " " + f.metavar, f.help, width);
  fmt::print("\nSettings [default] (commands they apply to):\n");
  const Settings defaults;
  for (const SettingSpec& s : settings_schema()) {
    std::string value = s.default_text.empty() ? s.format(defaults) : std::string(s.default_text);
    std::string flag = std::string(s.flag) + " " + std::string(s.metavar);
    if (!s.alias.empty()) flag = std::string(s.alias) + ", " + flag;
    print_entry(flag, std::string(s.help) + " [" + value + "] (" + commands_list(s.commands) + ")",
                width);
  }
  fmt::print("\nGeneral:\n");
  print_entry("-v", "Verbose: stages, colour-space choice, cache statistics", width);
  print_entry("-q", "Quiet: no progress, summary or warnings", width);
  print_entry("-h, --help", "Print this help and exit", width);
  print_entry("--version",
              "Print the version (and the OpenImageIO, OpenColorIO and OpenEXR it uses) and exit",
              width);
  print_entry("--", "Everything after it is an input file, even if it starts with '-'", width);
  print_entry("--force", "ingest: convert even what is up to date", width);
  print_entry("--merge", "ingest: merge the shards' manifests of -o DESTDIR into one", width);
  fmt::print(
      "\nExit status: 0 done (warnings on stderr), 1 the job failed (the message names the "
      "file), 2 a wrong command line.\n");
}

// Binds a flag to the list of (flag, value) pairs; validation happens once the command is
// known, so every message names the flag and the value.
auto store(std::vector<std::pair<std::string, std::string>>& given, std::string flag) {
  return [&given, flag](OIIO::cspan<const char*> args) { given.emplace_back(flag, args[1]); };
}

using Given = std::vector<std::pair<std::string, std::string>>;

// Parses argv with OIIO's ArgParse into (flag, value) pairs and positional inputs; "--" ends
// the options (what follows are input files, whatever their names). Throws UsageError.
Given read_flags(int argc, const char** argv, Options& opt, bool& help, bool& version) {
  std::vector<const char*> args;
  std::vector<std::string> after_dashes;
  std::vector<std::string> merged;  // "--tile W H" as oiiotool spells it becomes "--tile W,H"
  merged.reserve(static_cast<std::size_t>(argc));
  auto whole = [](const char* t) {
    return *t && std::string(t).find_first_not_of("0123456789") == std::string::npos;
  };
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && std::string(argv[i]) == "--") {
      for (int k = i + 1; k < argc; ++k) after_dashes.emplace_back(argv[k]);
      break;
    }
    args.push_back(argv[i]);
    if (std::string(argv[i]) == "--tile" && i + 2 < argc && whole(argv[i + 1]) &&
        whole(argv[i + 2])) {
      merged.push_back(std::string(argv[i + 1]) + "," + argv[i + 2]);
      args.push_back(merged.back().c_str());
      i += 2;
    }
  }
  Given given;
  OIIO::ArgParse ap;
  ap.add_help(false).exit_on_error(false);
  ap.arg("filename").hidden().action([&](OIIO::cspan<const char*> a) {
    opt.inputs.emplace_back(a[0]);
  });
  ap.arg("--help").hidden().action([&](OIIO::cspan<const char*>) { help = true; });
  ap.arg("-h").hidden().action([&](OIIO::cspan<const char*>) { help = true; });
  ap.arg("--version").hidden().action([&](OIIO::cspan<const char*>) { version = true; });
  ap.arg("-v").hidden().action([&](OIIO::cspan<const char*>) {
    opt.verbosity = 2;
    opt.given.insert("-v");
  });
  ap.arg("-q").hidden().action([&](OIIO::cspan<const char*>) {
    opt.verbosity = 0;
    opt.given.insert("-q");
  });
  ap.arg("--force").hidden().action([&](OIIO::cspan<const char*>) {
    opt.force = true;
    opt.given.insert("--force");
  });
  ap.arg("--merge").hidden().action([&](OIIO::cspan<const char*>) {
    opt.merge = true;
    opt.given.insert("--merge");
  });
  for (const CommandFlag& f : kCommandFlags)
    ap.arg((std::string(f.flag) + " " + f.metavar).c_str()).hidden().action(store(given, f.flag));
  std::set<std::string> registered;
  for (const SettingSpec& s : settings_schema())
    for (std::string_view flag : {s.flag, s.alias})
      if (!flag.empty() && registered.insert(std::string(flag)).second)
        ap.arg((std::string(flag) + " " + std::string(s.metavar)).c_str())
            .hidden()
            .action(store(given, std::string(flag)));
  if (ap.parse_args(static_cast<int>(args.size()), args.data()) < 0)
    throw UsageError{clip(ap.geterror(), 300)};
  for (auto& f : after_dashes) opt.inputs.push_back(std::move(f));
  return given;
}

// Which command the flags and inputs ask for; names the common slips. Throws UsageError.
Command choose_command(Options& opt) {
  if (!opt.inputs.empty() && opt.inputs[0] == "ingest") {
    opt.inputs.erase(opt.inputs.begin());
    return kIngest;
  }
  if (!opt.inputs.empty() && opt.inputs[0] == "table") {
    opt.inputs.erase(opt.inputs.begin());
    return kTable;
  }
  if (opt.force || opt.merge)
    throw UsageError{std::string(opt.force ? "--force" : "--merge") + " belongs to ingest"};
  if (!opt.plot_pixels.empty()) return kPlotPixel;
  if (!opt.colors.empty()) {
    if (!opt.inputs.empty()) {
      bool numbers = true;
      for (const std::string& in : opt.inputs)
        numbers = numbers && in.find_first_not_of("0123456789.+-eE") == std::string::npos;
      if (numbers)
        throw UsageError{"--color takes R,G,B as one argument with commas: --color " +
                         clip(opt.colors.back()) + "," + opt.inputs[0] +
                         (opt.inputs.size() > 1 ? "," + opt.inputs[1] : "")};
      throw UsageError{"give one of --color, --to-rgb or an input image, not several"};
    }
    return !opt.output.empty() && is_plot_path(opt.output) ? kPlotColor : kColor;
  }
  if (opt.given.count("--to-rgb")) {
    if (!opt.inputs.empty()) throw UsageError{"give one of --to-rgb or an input image, not both"};
    return kToRgb;
  }
  if (!opt.inputs.empty() || opt.given.count("-o")) return kImage;
  throw UsageError{
      "nothing to do: give INPUT -o OUTPUT.exr, --to-rgb IN.exr -o OUT.exr or "
      "--color R,G,B"};
}

// Every flag must apply to the command, and every value must pass the schema.
void apply_flags(const Given& given, Options& opt) {
  for (const auto& [flag, value] : given) {
    bool command_flag = false;
    for (const CommandFlag& f : kCommandFlags)
      if (flag == f.flag) {
        command_flag = true;
        if (!(f.commands & opt.command))
          throw UsageError{flag + " does not apply to " + command_name(opt.command)};
      }
    if (command_flag) continue;
    const SettingSpec* spec = find_setting_for_flag(flag, opt.command);
    if (!spec)
      throw UsageError{flag + " does not apply to " + command_name(opt.command) +
                       " (it applies to " + commands_list(flag_commands(flag)) + ")"};
    usage_checked("", [&] { apply_setting(opt.settings, *spec, value, flag); });
  }
}

// Reads the command line into `opt`; throws UsageError.
void parse(int argc, const char** argv, Options& opt, bool& help, bool& version) {
  const Given given = read_flags(argc, argv, opt, help, version);
  if (help || version) return;
  for (const auto& [flag, value] : given) {
    opt.given.insert(flag);
    if (flag == "--color") opt.colors.push_back(value);
    if (flag == "--plot-pixel") opt.plot_pixels.push_back(value);
    if (flag == "-o") opt.output = value;
    if (flag == "--report") opt.report = value;
    if (flag == "--to-rgb") opt.to_rgb = value;
    if (flag == "--inputs-from") opt.inputs_from = value;
    if (flag == "--manifest") opt.manifest = value;
    if (flag == "--shard") opt.shard = value;
  }
  for (const auto& [flag, value] : given)
    if ((flag == "-o" || flag == "--report" || flag == "--to-rgb" || flag == "--inputs-from" ||
         flag == "--manifest") &&
        value.empty())
      throw UsageError{flag + ": an empty file name"};
  opt.command = choose_command(opt);
  apply_flags(given, opt);
}

}  // namespace

int main(int argc, const char** argv) {
  install_cleanup_handlers();
  // No output of this run replaces a file it reads (docs/DESIGN.md §9).
  const ReadFileScope reads;
  Options opt;
  bool help = false, version = false;
  try {
    parse(argc, argv, opt, help, version);
    if (help) {
      print_help();
      check_stdout();
      return kExitOk;
    }
    if (version) {
      // The libraries whose behaviour the output depends on, as OIIO tools' --version says its own.
      fmt::print("spectralize " SPECTRALIZE_VERSION
                 "\nOpenImageIO {}, OpenColorIO {}, OpenEXR {}\n",
                 OIIO_VERSION_STRING, ColourSpaces::ocio_version(), openexr_version());
      check_stdout();
      return kExitOk;
    }
    int status = kExitOk;
    switch (opt.command) {
      case kPlotPixel:
        status = run_plot_pixel(opt);
        break;
      case kPlotColor:
        status = run_plot_color(opt);
        break;
      case kColor:
        status = run_color(opt);
        break;
      case kToRgb:
        status = run_to_rgb(opt);
        break;
      case kIngest:
        status = run_ingest_command(opt);
        break;
      case kTable:
        status = run_table(opt);
        break;
      default:
        status = run_image(opt);
        break;
    }
    check_stdout();
    return status;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "spectralize ERROR: %s\nRun 'spectralize --help' for the options.\n",
                 e.message.c_str());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spectralize ERROR: %s\n", e.what());
    return kExitFailure;
  }
}
