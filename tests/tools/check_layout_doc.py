#!/usr/bin/env python3
"""The source-layout chapter (docs/guide/layout.md) describes the tree as it is: every folder of
src/ (and src/core/'s), include/spectralize/, tests/ and the top level is named in it as
`path/`, and every repository path it names in backquotes exists. Prints each slip; exit 1 if
any. Usage: check_layout_doc.py SOURCE_DIR"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1]).resolve()
text = (root / "docs/guide/layout.md").read_text()
named = set(re.findall(r"`([^`\s]+)`", text))
# Folders under version control only (a build tree or a cache is not the layout); outside a
# git checkout, the files but build trees and hidden folders.
try:
    listing = subprocess.run(["git", "-C", str(root), "ls-files"], capture_output=True, text=True)
except OSError:  # no git (a minimal root): the files instead
    listing = None
if listing is not None and listing.returncode == 0:
    tracked = listing.stdout.split()
else:
    tracked = [str(p.relative_to(root)) for p in root.rglob("*") if p.is_file()
               and not any(part.startswith((".", "build")) for part in p.relative_to(root).parts[:-1])]
folders = set()
for f in tracked:
    parts = pathlib.PurePosixPath(f).parts[:-1]
    for i in range(1, len(parts) + 1):
        folders.add("/".join(parts[:i]))


def wanted(folder):
    top = folder.split("/")[0]
    depth = folder.count("/")
    if folder.startswith("src/core/"):
        return depth == 2
    if top in ("src", "tests"):
        return depth == 1
    if folder.startswith("include/spectralize"):
        return folder == "include/spectralize"
    if top == "docs":
        return False  # named by the chapter where they matter (guide, examples, ...)
    return depth == 0 and not top.startswith(".") or folder == ".ci"


bad = []
for folder in sorted(f for f in folders if wanted(f)):
    # Named itself, or through a path inside it (include/ by include/spectralize/).
    if not any(n == folder or n.startswith(folder + "/") for n in named):
        bad.append(f"docs/guide/layout.md does not name the folder {folder}/")
# Every path the chapter names exists (relative to the root; a bare name is a file's stem).
for name in sorted(named):
    if "/" not in name or name.startswith(("http", "--")):
        continue
    path = name.rstrip("/")
    if not (root / path).exists() and not any(t.startswith(path) for t in tracked):
        bad.append(f"docs/guide/layout.md names {name}, which does not exist")
for b in bad:
    print(b)
sys.exit(1 if bad else 0)
