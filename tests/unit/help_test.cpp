// The command-line reference (src/tool/help.cpp): --help, the man page and the guide's chapter
// all list every flag of the settings schema and of the commands, each in its own syntax.
#include "tool/help.h"

#include <gtest/gtest.h>

#include <string>

namespace spectralize::tool {
namespace {

// Every flag the parser accepts (the schema's and the command flags), in each rendering: as
// typed in --help and the guide, as roff minus signs in the man page.
TEST(Help, EveryFlagIsInTheTextTheManPageAndTheGuide) {
  const std::string text = help_text(100), man = help_man(), md = help_markdown();
  int flags = 0;
  auto roff = [](std::string f) {
    std::string out;
    for (char c : f) out += c == '-' ? std::string("\\-") : std::string(1, c);
    return out;
  };
  for (const SettingSpec& s : settings_schema()) {
    const std::string flag(s.flag);
    EXPECT_NE(text.find(flag), std::string::npos) << flag;
    EXPECT_NE(md.find(flag + " "), std::string::npos) << flag;
    EXPECT_NE(man.find(roff(flag)), std::string::npos) << flag;
    ++flags;
  }
  for (const CommandFlag& f : command_flags()) {
    EXPECT_NE(text.find(f.flag), std::string::npos) << f.flag;
    EXPECT_NE(md.find(std::string(f.flag) + " "), std::string::npos) << f.flag;
    EXPECT_NE(man.find(roff(f.flag)), std::string::npos) << f.flag;
  }
  EXPECT_GT(flags, 25);
}

// Each syntax's own escapes: no bare hyphen of a flag in roff, no line that roff would take
// for a request, no unescaped '|' inside a Markdown table's code span.
TEST(Help, EachRenderingEscapesForItsFormat) {
  const std::string man = help_man(), md = help_markdown();
  EXPECT_EQ(man.rfind(".TH SPECTRALIZE 1", 0), 0u);
  EXPECT_EQ(man.find(" --"), std::string::npos);
  EXPECT_NE(md.find("PLOT.png\\|PLOT.svg"), std::string::npos);
  std::size_t start = 0;
  while (start < man.size()) {
    const std::size_t end = man.find('\n', start);
    const std::string line = man.substr(start, end - start);
    if (!line.empty() && line[0] == '\'') ADD_FAILURE() << line;
    start = end == std::string::npos ? man.size() : end + 1;
  }
}

// Each command's page of the guide lists exactly the settings that apply to it, with defaults.
TEST(Help, EachCommandsPageHoldsItsFlagsAndNoOthers) {
  EXPECT_EQ(command_pages().size(), 7u);
  for (const auto& [name, command] : command_pages()) {
    const std::string page = help_markdown_for(command);
    for (const SettingSpec& s : settings_schema()) {
      const std::string flag = std::string(s.flag) + " ";
      const bool listed = page.find(std::string("`").append(flag)) != std::string::npos ||
                          page.find(std::string(", ").append(flag)) != std::string::npos;
      bool applies = false;  // a flag may be two settings (--format: samples, or CSV/JSON)
      for (const SettingSpec& other : settings_schema())
        applies = applies || (other.flag == s.flag && other.applies(command));
      EXPECT_EQ(listed, applies) << name << ": " << s.flag;
    }
  }
  EXPECT_NE(help_markdown_for(kTable).find("| `--rgb-to-xyz MATRIX` |"), std::string::npos);
}

// The settings' defaults are those --help states.
TEST(Help, SettingsCarryTheirDefaults) {
  const HelpDocument doc = help_document();
  bool grid = false;
  for (const HelpSection& s : doc.sections)
    for (const HelpEntry& e : s.entries)
      if (e.flag.find("--wavelengths") != std::string::npos) {
        grid = true;
        EXPECT_EQ(e.default_value, "380:780:5");
      }
  EXPECT_TRUE(grid);
}

}  // namespace
}  // namespace spectralize::tool
