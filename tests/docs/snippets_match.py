#!/usr/bin/env python3
"""docs/RENDERERS.md shows its code verbatim from docs/snippets/, which the test suite builds
and runs: every block marked `<!-- snippet: docs/snippets/NAME -->` must equal that file, and
every file in docs/snippets/ must be shown. Usage: snippets_match.py SOURCE_DIR [--update]
(--update rewrites the document's copies from the files)."""
import os
import re
import sys


def main():
    source = sys.argv[1]
    doc_path = os.path.join(source, "docs", "RENDERERS.md")
    text = open(doc_path, encoding="utf-8").read()
    if "--update" in sys.argv[2:]:
        def copy(m):
            return m.group(1) + open(os.path.join(source, m.group(2)), encoding="utf-8").read() + "```\n"
        text = re.sub(r"(<!-- snippet: (\S+) -->\n```[a-z+]*\n).*?```\n", copy, text, flags=re.S)
        open(doc_path, "w", encoding="utf-8").write(text)
    blocks = re.findall(r"<!-- snippet: (\S+) -->\n```[a-z+]*\n(.*?)```\n", text, re.S)
    failures = []
    shown = set()
    for path, code in blocks:
        shown.add(path)
        full = os.path.join(source, path)
        if not os.path.isfile(full):
            failures.append(f"{path}: shown in RENDERERS.md but no such file")
            continue
        if open(full, encoding="utf-8").read() != code:
            failures.append(f"{path}: RENDERERS.md's copy differs from the file")
    markers = len(re.findall(r"<!-- snippet: ", text))
    if markers != len(blocks):
        failures.append(f"{markers} snippet markers but {len(blocks)} code blocks after them")
    snippets = os.path.join(source, "docs", "snippets")
    for name in sorted(os.listdir(snippets)):
        if f"docs/snippets/{name}" not in shown and name != "CMakeLists.txt":
            failures.append(f"docs/snippets/{name}: not shown in RENDERERS.md")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print(f"ok: {len(blocks)} snippets match")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
