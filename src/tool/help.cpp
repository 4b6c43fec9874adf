#include "tool/help.h"

#include <cctype>
#include <string_view>
#include <utility>

#include "spectralize/version.h"

namespace spectralize::tool {

namespace {

constexpr unsigned kPlots = kPlotColor | kPlotPixel;

constexpr unsigned kAllCommands = kImage | kToRgb | kColor | kPlots | kIngest | kTable;

// The words of `text`, wrapped into lines that start at column `indent` and end by `width`
// (the first line continues `line`, whatever its length).
std::string wrapped(std::string line, std::string_view text, std::size_t indent, int width) {
  std::size_t col =
      line.size() - (line.rfind('\n') == std::string::npos ? 0 : line.rfind('\n') + 1);
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find(' ', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(pos, end - pos);
    if (col + word.size() + 1 > static_cast<std::size_t>(width) && col > indent) {
      line += "\n" + std::string(indent, ' ');
      col = indent;
    } else if (col > indent) {
      line += ' ';
      ++col;
    }
    line += word;
    col += word.size();
    pos = end + 1;
  }
  return line;
}

// roff: a backslash doubled, a hyphen made a minus (flags are typed with ASCII '-'), and a
// line that would start with a control character ('.' or '\'') protected.
std::string roff(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out.insert(0, "\\&");
  return out;
}

// Markdown (CommonMark, as MyST reads it): punctuation that would start markup escaped.
std::string markdown(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (std::string_view("\\`*_[]<>|#").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

// In a Markdown table cell even code spans end at '|' unless it is escaped.
std::string escaped_pipes(std::string_view text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

const std::vector<CommandFlag>& command_flags() {
  static const std::vector<CommandFlag> flags = {
      {"-o", "FILE", kImage | kToRgb | kColor | kPlots | kIngest | kTable,
       "The file to write: the spectral OpenEXR (images), the RGB image (--to-rgb), a plot "
       "(.png, .svg, ...), the printed spectra (--color: .csv, .json), the folder ingest "
       "writes into, or the table (NAME.spztab)"},
      {"--inputs-from", "FILE", kIngest,
       "ingest: a list of inputs, one per line: a path, or a JSON object with \"input\" and any "
       "single-file setting for it"},
      {"--manifest", "FILE", kIngest,
       "ingest: the JSON Lines record of what happened (default: "
       "DESTDIR/spectralize-ingest.jsonl, or a part per shard)"},
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
  return flags;
}

std::string command_name(Command command) {
  switch (command) {
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
  for (const CommandName& c : command_names())
    if ((commands & c.bit) && !(c.bit == kPlotColor && (commands & kColor)))
      out += (out.empty() ? "" : ", ") + std::string(c.name);
  return out;
}

std::string command_list_for_pages() {
  std::string out;
  for (const CommandName& c : command_names())
    out += (out.empty() ? "" : ", ") + std::string(c.name);
  return out;
}

HelpDocument help_document() {
  HelpDocument doc;
  doc.usage = {
      {"spectralize INPUT -o OUTPUT.exr [options]", "an RGB image to a spectral OpenEXR"},
      {"spectralize --to-rgb IN.exr -o OUT.exr [options]", "a spectral OpenEXR to RGB(A)"},
      {"spectralize --color R,G,B [--color ...] [options]", "spectra of colours (CSV, JSON)"},
      {"spectralize --color R,G,B [...] -o PLOT.png|PLOT.svg", "a plot of their spectra"},
      {"spectralize --plot-pixel X,Y IN.exr -o PLOT.png", "a plot of a pixel of a spectral EXR"},
      {"spectralize ingest SRC... -o DESTDIR [options]",
       "a texture library (files, folders, globs, a USD stage) to spectral OpenEXR"},
      {"spectralize table -o NAME.spztab [options]",
       "a render-time table of exact spectra (spectralize/rt.h)"},
  };
  HelpSection by_command{"Flags by command", {}};
  for (const CommandName& c : command_names()) {
    std::string flags;
    for (const CommandFlag& f : command_flags())
      if (f.commands & c.bit) flags += std::string(flags.empty() ? "" : " ") + f.flag;
    // Whole flags: "--data" is not "--data-names".
    auto has = [&](std::string_view flag) {
      const std::string padded = " " + flags + " ";
      return padded.find(" " + std::string(flag) + " ") != std::string::npos;
    };
    for (const SettingSpec& spec : settings_schema())
      if (spec.applies(c.bit) && !has(spec.flag)) flags.append(" ").append(spec.flag);
    if (c.bit == kIngest) flags += " --force --merge";  // ingest's own switches (General)
    by_command.entries.push_back({std::string(c.name), flags + " -v -q", "", ""});
  }
  HelpSection outputs{"Commands and outputs", {}};
  for (const CommandFlag& f : command_flags())
    outputs.entries.push_back({std::string(f.flag) + " " + f.metavar, f.help, "", "", f.commands});
  HelpSection settings{"Settings [default] (commands they apply to)", {}};
  const Settings defaults;
  for (const SettingSpec& s : settings_schema()) {
    std::string flag = std::string(s.flag) + " " + std::string(s.metavar);
    if (!s.alias.empty()) flag = std::string(s.alias) + ", " + flag;
    settings.entries.push_back(
        {flag, s.help, s.default_text.empty() ? s.format(defaults) : std::string(s.default_text),
         commands_list(s.commands), s.commands});
  }
  HelpSection general{"General", {}};
  general.entries = {
      {"-v", "Verbose: stages, colour-space choice, cache statistics", "", "", kAllCommands},
      {"-q", "Quiet: no progress, summary or warnings", "", "", kAllCommands},
      {"-h, --help", "Print this help and exit", "", ""},
      {"--version",
       "Print the version (and the OpenImageIO, OpenColorIO and OpenEXR it uses) and exit", "", ""},
      {"--help-man", "Print this reference as a man page (roff) and exit", "", ""},
      {"--help-markdown", "Print this reference as Markdown (the guide's flag chapter) and exit",
       "", ""},
      {"--help-markdown-for COMMAND",
       "Print the flags of one command as a Markdown table and exit; COMMAND is one of " +
           command_list_for_pages() + " (the leading -- may be left out)",
       "", ""},
      {"--", "Everything after it is an input file, even if it starts with '-'", "", ""},
      {"--force", "ingest: convert even what is up to date", "", ""},
      {"--merge", "ingest: merge the shards' manifests of -o DESTDIR into one", "", ""},
  };
  doc.sections = {by_command, outputs, settings, general};
  doc.exit_status =
      "0 done (warnings on stderr), 1 the job failed (the message names the file), 2 a wrong "
      "command line.";
  return doc;
}

std::string help_text(int width) {
  constexpr std::size_t kColumn = 26;
  const HelpDocument doc = help_document();
  std::string out =
      "spectralize " SPECTRALIZE_VERSION
      " -- exact RGB-to-spectrum conversion (Zhdanov & Potemin)\n"
      "Every spectrum reproduces its input colour exactly, is non-negative, and a reflectance "
      "stays <= 1.\n\nUsage:\n";
  for (const auto& [command, what] : doc.usage) {
    std::string line = "  " + command;
    line += std::string(line.size() < 56 ? 56 - line.size() : 1, ' ');
    out += wrapped(line, what, 56, 95) + "\n";
  }
  for (const HelpSection& section : doc.sections) {
    out += "\n" + section.title + ":\n";
    for (const HelpEntry& e : section.entries) {
      std::string line = "  " + e.flag;
      line += line.size() + 1 < kColumn ? std::string(kColumn - line.size(), ' ')
                                        : "\n" + std::string(kColumn, ' ');
      std::string text = e.text;
      if (!e.commands.empty()) text += " [" + e.default_value + "] (" + e.commands + ")";
      out += wrapped(line, text, kColumn, width) + "\n";
    }
  }
  out += "\nExit status: " + doc.exit_status + "\n";
  return out;
}

std::string help_man() {
  const HelpDocument doc = help_document();
  std::string out =
      ".TH SPECTRALIZE 1 \"\" \"spectralize " SPECTRALIZE_VERSION
      "\" \"User Commands\"\n"
      ".nh\n.ad l\n"  // flags neither hyphenated nor stretched
      ".SH NAME\nspectralize \\- exact RGB\\-to\\-spectrum conversion of images, colours and "
      "texture libraries\n.SH SYNOPSIS\n";
  for (const auto& [command, what] : doc.usage)
    out += ".PP\n" + roff(command) + "\n.RS\n" + roff(what) + "\n.RE\n";
  out +=
      ".SH DESCRIPTION\nEvery spectrum reproduces its input colour exactly, is non\\-negative, "
      "and a reflectance stays <= 1. Colours are read in any OpenColorIO colour space; spectra "
      "are written as spectral OpenEXR files, printed, plotted, or stored in a render\\-time "
      "table for renderers.\n";
  for (const HelpSection& section : doc.sections) {
    std::string title = section.title.substr(0, section.title.find(" ["));
    for (char& c : title) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    out += ".SH " + title + "\n";
    for (const HelpEntry& e : section.entries) {
      out += ".TP\n.B " + roff(e.flag) + "\n" + roff(e.text);
      if (!e.commands.empty())
        out += ".\nDefault: " + roff(e.default_value) + ". Applies to: " + roff(e.commands) + ".";
      out += "\n";
    }
  }
  out += ".SH EXIT STATUS\n" + roff(doc.exit_status) +
         "\n.SH ENVIRONMENT\n.TP\n.B OCIO\nThe OpenColorIO config to use when \\-\\-config is not "
         "given (else the shipped one).\n.SH SEE ALSO\noiiotool(1), ociocheck(1); the user guide, "
         "installed under share/doc/spectralize/html.\n";
  return out;
}

std::string help_markdown() {
  const HelpDocument doc = help_document();
  std::string out =
      "# Command-line reference\n\n"
      "Every flag of `spectralize`, as `spectralize --help` prints it and `man spectralize` "
      "shows it: the three are made from the same settings schema when the project builds.\n\n"
      "## Usage\n\n| Command | What it does |\n|---|---|\n";
  for (const auto& [command, what] : doc.usage)
    out += "| `" + escaped_pipes(command) + "` | " + markdown(what) + " |\n";
  for (const HelpSection& section : doc.sections) {
    out += "\n## " + section.title.substr(0, section.title.find(" [")) + "\n\n";
    if (section.title == "Flags by command") {
      out += "| Command | Flags |\n|---|---|\n";
      for (const HelpEntry& e : section.entries) out += "| `" + e.flag + "` | `" + e.text + "` |\n";
      continue;
    }
    for (const HelpEntry& e : section.entries) {
      out += "`" + e.flag + "`\n: " + markdown(e.text);
      if (!e.commands.empty())
        out += ". Default: `" + e.default_value + "`. Applies to: " + markdown(e.commands) + ".";
      out += "\n\n";
    }
  }
  out += "## Exit status\n\n" + markdown(doc.exit_status) + "\n";
  return out;
}

const std::vector<std::pair<std::string, Command>>& command_pages() {
  static const std::vector<std::pair<std::string, Command>> pages = [] {
    std::vector<std::pair<std::string, Command>> out;
    for (const CommandName& c : command_names()) out.emplace_back(c.page(), c.bit);
    return out;
  }();
  return pages;
}

std::string help_markdown_for(Command command) {
  // The reference's entries that serve this command, in its order: command flags, settings
  // (with their defaults), then -v and -q.
  std::string out = "| Flag | What it does | Default |\n|---|---|---|\n";
  for (const HelpSection& section : help_document().sections)
    for (const HelpEntry& e : section.entries)
      if (e.command_bits & command)
        out +=
            "| `" + escaped_pipes(e.flag) + "` | " + markdown(e.text) + " | " +
            (e.default_value.empty() ? std::string() : "`" + escaped_pipes(e.default_value) + "`") +
            " |\n";
  return out;
}

}  // namespace spectralize::tool
