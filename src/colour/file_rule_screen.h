#pragma once
// A screen in front of OpenColorIO's file rules (docs/DESIGN.md §9). OCIO builds and compiles
// each rule's regular expression on every match (~1 ms a path for a handful of rules), so a
// batch of many small files paid more for its file rules than for its pixels. The screen reads
// each glob rule once, as a pattern that matches at least what OCIO's expression matches
// (letters without case, anything it cannot read as "anything"), and tells the paths no rule
// but the default can match; only the others are given to OCIO, whose answer is the decision.

#include <string>
#include <string_view>
#include <vector>

namespace spectralize {

/// One of a config's file rules, as OCIO states it.
struct FileRuleText {
  enum class Kind { glob, other, fallback };  // pattern + extension; regex or path search; Default
  Kind kind = Kind::glob;
  std::string pattern, extension;  // a glob rule's
};

class FileRuleScreen {
 public:
  /// The screen of `rules` (in the config's order, the default last). Cost: O(rules' text).
  explicit FileRuleScreen(const std::vector<FileRuleText>& rules);

  /// False only when no rule but the default can match `path`; true when one may (OCIO
  /// decides). Cost: O(rules x pattern x path) at worst, one lower-case copy of the path.
  bool may_match(std::string_view path) const;

  /// One step of a read glob: a character, any one, one of a set, or any run.
  struct Element {
    enum Kind { literal, one, set, run } kind = literal;
    std::string chars;  // lower case: the literal, or the set's members
  };

 private:
  bool always_ = false;                      // a rule the screen cannot read (regex, search)
  std::vector<std::vector<Element>> globs_;  // per glob rule, "<pattern>.<extension>", anchored
};

}  // namespace spectralize
