#!/usr/bin/env python3
"""Nothing of the former long README is lost: every section listed in readme_sections.txt
(heading, tab, file) is a heading of that file of the guide, at any level, and the introduction's text is
in docs/index.md; the README's links into the repository (the guide's chapters) resolve.
Usage: sections_moved.py SOURCE_DIR"""
import os
import re
import sys


def main():
    source = sys.argv[1]
    listed, missing = 0, []
    for line in open(os.path.join(source, "tests", "docs", "readme_sections.txt"), encoding="utf-8"):
        if line.startswith("# ") and "\t" not in line or not line.strip():
            continue
        heading, path = line.rstrip("\n").split("\t")
        listed += 1
        lines = open(os.path.join(source, path), encoding="utf-8").read().split("\n")
        titles = {l.lstrip("#").strip() for l in lines if l.startswith("#")}
        if heading.lstrip("#").strip() not in titles and not (
                path == "docs/index.md" and lines and lines[0].startswith("# spectralize")):
            missing.append(f"{heading} (in {path})")
    readme = open(os.path.join(source, "README.md"), encoding="utf-8").read()
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", readme)
    for target in links:
        if "://" not in target and not os.path.exists(os.path.join(source, target)):
            missing.append(f"README link {target}")
    for m in missing:
        print("MISSING:", m)
    print(f"{listed} sections listed, {len(links)} README links, {len(missing)} missing")
    return 1 if missing or listed < 20 else 0


if __name__ == "__main__":
    sys.exit(main())
