#include "colour/file_rule_screen.h"

#include <algorithm>
#include <cctype>

namespace spectralize {

namespace {

char lower(char c) {
  return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
}

using Element = FileRuleScreen::Element;

// A bracket expression's characters, lower case, when it is plain (letters, digits and ranges
// of them); false for any other, which the screen takes as any one character (a bracket always
// stands for exactly one). A negated one ('!') is any other: "[!a]" matches "A", which a set
// compared without case would refuse.
bool plain_class(std::string_view body, Element& e) {
  if (body.empty() || body[0] == '!') return false;
  auto plain = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (!plain(body[i])) return false;
    if (i + 2 < body.size() && body[i + 1] == '-') {
      if (!plain(body[i + 2]) || body[i + 2] < body[i]) return false;
      for (char c = body[i]; c <= body[i + 2]; ++c) e.chars += lower(c);
      i += 2;
    } else {
      e.chars += lower(body[i]);
    }
  }
  return true;
}

// A glob as OCIO turns it into its expression (FileRules: '*' any run, '?' any character,
// brackets a class, a backslash passed on as the expression's escape, everything else itself),
// read so that it matches at least what the expression matches: letters without case, a
// backslash sequence ("\d", "\b", ...) as any run, a bracket the screen cannot read as any one
// character.
void read_glob(std::string_view glob, std::vector<Element>& out) {
  for (std::size_t i = 0; i < glob.size(); ++i) {
    Element e;
    const char c = glob[i];
    if (c == '*' || c == '\\') {
      e.kind = Element::run;
      if (c == '\\') ++i;
    } else if (c == '?') {
      e.kind = Element::one;
    } else if (c == '[') {
      const std::size_t close = glob.find(']', i + 1);
      if (close == std::string_view::npos) {  // OCIO refuses it at load: anything
        out.push_back({Element::run, ""});
        return;
      }
      e.kind = plain_class(glob.substr(i + 1, close - i - 1), e) ? Element::set : Element::one;
      if (e.kind == Element::one) e.chars.clear();
      i = close;
    } else {
      e.kind = Element::literal;
      e.chars = std::string(1, lower(c));
    }
    if (e.kind == Element::run && !out.empty() && out.back().kind == Element::run) continue;
    out.push_back(std::move(e));
  }
}

bool matches_one(const Element& e, char c) {
  switch (e.kind) {
    case Element::literal:
      return e.chars[0] == c;
    case Element::one:
      return true;
    case Element::set:
      return e.chars.find(c) != std::string::npos;
    case Element::run:
      return false;
  }
  return false;
}

// The whole of `text` against `elements` (each one character but runs, which take any number):
// the classic wildcard walk, backing up to the last run. Cost: O(text x elements) at worst.
bool matches(const std::vector<Element>& elements, std::string_view text) {
  std::size_t e = 0, t = 0, star = std::string_view::npos, star_t = 0;
  while (t < text.size()) {
    if (e < elements.size() && elements[e].kind == Element::run) {
      star = e++, star_t = t;
    } else if (e < elements.size() && matches_one(elements[e], text[t])) {
      ++e, ++t;
    } else if (star != std::string_view::npos) {
      e = star + 1, t = ++star_t;
    } else {
      return false;
    }
  }
  while (e < elements.size() && elements[e].kind == Element::run) ++e;
  return e == elements.size();
}

}  // namespace

FileRuleScreen::FileRuleScreen(const std::vector<FileRuleText>& rules) {
  for (const FileRuleText& rule : rules) {
    if (rule.kind == FileRuleText::Kind::fallback) continue;
    if (rule.kind == FileRuleText::Kind::other) {
      always_ = true;
      continue;
    }
    // OCIO's expression is "^((<pattern>)(\.<extension>))$", an empty pattern or extension
    // being "anything".
    std::vector<Element> elements;
    read_glob(rule.pattern.empty() ? std::string_view("*") : rule.pattern, elements);
    elements.push_back({Element::literal, "."});
    read_glob(rule.extension.empty() ? std::string_view("*") : rule.extension, elements);
    globs_.push_back(std::move(elements));
  }
}

bool FileRuleScreen::may_match(std::string_view path) const {
  if (always_) return true;
  if (globs_.empty()) return false;
  std::string low(path);
  std::transform(low.begin(), low.end(), low.begin(), lower);
  return std::any_of(globs_.begin(), globs_.end(),
                     [&](const std::vector<Element>& glob) { return matches(glob, low); });
}

}  // namespace spectralize
