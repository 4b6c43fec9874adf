#pragma once
// The command line's reference, made once from the settings schema and the command flags: what
// `--help` prints, the man page (spectralize.1) and the guide's flag chapter, so none of them can
// say other than the parser accepts.

#include <string>
#include <vector>

#include "settings/settings.h"

namespace spectralize::tool {

/// A flag that is not a setting: what to do and where to write, with the commands it serves.
struct CommandFlag {
  const char* flag;
  const char* metavar;
  unsigned commands;
  const char* help;
};

/// The command flags, in --help order. Cost: O(1).
const std::vector<CommandFlag>& command_flags();

/// "an image conversion (INPUT -o OUTPUT.exr)", "ingest"...: a command in a message. Cost: O(1).
std::string command_name(Command command);

/// "image, --to-rgb, table": the commands of a bit set, as --help lists them. Cost: O(1).
std::string commands_list(unsigned commands);

/// One entry of the reference: the flag as typed (with its value) and its text.
struct HelpEntry {
  std::string flag, text;
  std::string default_value;  // settings: the default ("" for other flags)
  std::string commands;       // settings: the commands it applies to ("" for other flags)
  unsigned command_bits = 0;  // the Command bits it serves (0: none in particular)
};

/// A titled list of entries.
struct HelpSection {
  std::string title;
  std::vector<HelpEntry> entries;
};

/// The whole reference: usage lines (command, what it does), sections, exit status.
struct HelpDocument {
  std::vector<std::pair<std::string, std::string>> usage;
  std::vector<HelpSection> sections;  // "Flags by command", "Commands and outputs", ...
  std::string exit_status;
};

/// The reference from the schema. Cost: O(settings).
HelpDocument help_document();

/// --help: the reference wrapped at `width` columns. Cost: O(settings).
std::string help_text(int width);

/// The reference as a man(7) page, section 1. Cost: O(settings).
std::string help_man();

/// The reference as a Markdown chapter of the guide. Cost: O(settings).
std::string help_markdown();

/// The commands by their guide pages' names (settings' command_names() without the leading
/// "--": "image", "to-rgb", "color", "plot", "plot-pixel", "ingest", "table"), with their bits.
/// Cost: O(1).
const std::vector<std::pair<std::string, Command>>& command_pages();

/// "image, --to-rgb, ...": the names --help-markdown-for takes (a leading "--" optional), for
/// --help and its error. Cost: O(commands).
std::string command_list_for_pages();

/// Every flag of one command as a Markdown table (flag, what it does, default), for that
/// command's chapter of the guide. Cost: O(settings).
std::string help_markdown_for(Command command);

}  // namespace spectralize::tool
