// spectralize: RGB colours and images to exact spectra (see README.md and the guide in docs/).

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
#include "tool/colour_values.h"
#include "tool/help.h"
#include "tool/options.h"

using namespace spectralize;
using namespace spectralize::tool;

namespace {

// The command `--help-markdown-for NAME` names (as --help names it, the leading "--" optional);
// a UsageError listing the names for another.
Command command_page(const std::string& name) {
  for (const CommandName& c : command_names())
    if (name == c.name || name == c.page()) return c.bit;
  throw UsageError{"--help-markdown-for " + quote(name) + ": not a command (valid: " +
                   command_list_for_pages() + "; the leading -- may be left out)"};
}

int terminal_width() {
  struct winsize w = {};
  if (::isatty(STDOUT_FILENO) && ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col >= 40)
    return w.ws_col;
  return 100;
}

// Binds a flag to the list of (flag, value) pairs; validation happens once the command is
// known, so every message names the flag and the value.
auto store(std::vector<std::pair<std::string, std::string>>& given, std::string flag) {
  return [&given, flag](OIIO::cspan<const char*> args) { given.emplace_back(flag, args[1]); };
}

using Given = std::vector<std::pair<std::string, std::string>>;

// Parses argv with OIIO's ArgParse into (flag, value) pairs and positional inputs; "--" ends
// the options (what follows are input files, whatever their names). Throws UsageError.
Given read_flags(int argc, const char** argv, Options& opt, std::string& help, bool& version) {
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
  ap.arg("--help").hidden().action([&](OIIO::cspan<const char*>) { help = "text"; });
  ap.arg("-h").hidden().action([&](OIIO::cspan<const char*>) { help = "text"; });
  // The same reference as a man page and as the guide's chapter (what the build installs).
  ap.arg("--help-man").hidden().action([&](OIIO::cspan<const char*>) { help = "man"; });
  ap.arg("--help-markdown").hidden().action([&](OIIO::cspan<const char*>) { help = "markdown"; });
  ap.arg("--help-markdown-for %s:COMMAND").hidden().action([&](OIIO::cspan<const char*> a) {
    help = std::string("markdown:") + a[1];
  });
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
  for (const CommandFlag& f : command_flags())
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
    for (const CommandFlag& f : command_flags())
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
void parse(int argc, const char** argv, Options& opt, std::string& help, bool& version) {
  const Given given = read_flags(argc, argv, opt, help, version);
  // The reference's generators write one document: anything else given is a slip.
  if (!help.empty() && help != "text" &&
      (!given.empty() || !opt.given.empty() || !opt.inputs.empty() || version))
    throw UsageError{"--help-man, --help-markdown and --help-markdown-for take nothing else; " +
                     (opt.inputs.empty() ? std::string("remove the other flags")
                                         : "'" + clip(opt.inputs.front()) + "' is not theirs")};
  if (!help.empty() || version) return;
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
  std::string help;  // "text", "man" or "markdown"
  bool version = false;
  try {
    parse(argc, argv, opt, help, version);
    if (!help.empty()) {
      fmt::print("{}", help == "man"        ? help_man()
                       : help == "markdown" ? help_markdown()
                       : help.rfind("markdown:", 0) == 0
                           ? help_markdown_for(command_page(help.substr(9)))
                           : help_text(terminal_width()));
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
