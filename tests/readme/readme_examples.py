#!/usr/bin/env python3
"""Runs the shell examples of README.md and checks their shown output.

Three kinds of blocks are examples:
  ```sh blocks        every command must succeed (run as one bash script, `set -e`);
  ```python blocks    must run (with the build's module on PYTHONPATH, matplotlib's Agg
                      backend); a ```text block right after one is its output and must match;
  ``` blocks of "$ "  each "$ command" is run; the lines after it, up to the next "$ ", are its
                      output (stdout and stderr together) and must match.

A block inside a list item (its fence indented) is an example too, read without the indent.

Matching: timings ("1.18 s", "0.004") are not compared where the README marks them as such
(a number followed by " s" in a summary line); a line ending in "..." or "... (abridged)" matches
any line that starts the same way; a line "..." skips any lines; JSON output is compared key by
key, numbers to 1e-12 relative (arrays shown with "..." compare their first elements). Blocks of top-level `make` commands
are skipped (this script is run by `make test`).

Usage: readme_examples.py DOC.md [DOC.md...] BUILD_DIR SOURCE_DIR
(several documents run as one, in the order given, in one working folder)
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

TIMING = re.compile(r"\b\d+(\.\d+)? s\b")


def blocks(text):
    """(kind, lines) for the example blocks: 'sh', 'python', 'text' or 'dollar'."""
    out, lines, kind, inside, indent = [], [], None, False, 0
    for line in text.split("\n"):
        # A fence may be indented (a block inside a list item); its lines lose that indent.
        if line.lstrip(" ").startswith("```") and (inside or len(line) - len(line.lstrip(" ")) < 4):
            if not inside:
                indent = len(line) - len(line.lstrip(" "))
            line = line[indent:] if line[:indent].strip() == "" else line
        if line.startswith("```"):
            if inside:
                if kind in ("sh", "python", "text"):
                    out.append((kind, lines))
                elif any(l.startswith("$ ") for l in lines):
                    out.append(("dollar", lines))
                lines, inside = [], False
            else:
                inside, kind = True, line[3:].strip()
            continue
        if inside:
            lines.append(line[indent:] if line[:indent].strip() == "" else line)
    return out


def normalise(line):
    return TIMING.sub("<t> s", line.rstrip())


def line_matches(shown, actual):
    shown, actual = normalise(shown), normalise(actual)
    if shown.endswith("... (abridged)"):
        shown = shown[: -len("... (abridged)")]
        return actual.startswith(shown.rstrip())
    if shown.endswith("..."):
        return actual.startswith(shown[:-3].rstrip())
    return shown == actual


def lines_match(shown, actual):
    """Shown lines appear in order: each matches the next output line, or, after a "..." line,
    some later one. Returns None or what did not match."""
    k, skipping = 0, False
    for s in shown:
        if s.strip() == "...":
            skipping = True
            continue
        while skipping and k < len(actual) and not line_matches(s, actual[k]):
            k += 1
        if k >= len(actual) or not line_matches(s, actual[k]):
            return f"shown line not in the output: {s}"
        k, skipping = k + 1, False
    return None


def same_value(shown, actual):
    """Equal, numbers to 1e-12 relative: the shown digits come from one compiler's rounding."""
    if isinstance(shown, list) and isinstance(actual, list):
        return len(shown) == len(actual) and all(same_value(a, b) for a, b in zip(shown, actual))
    if isinstance(shown, float) and isinstance(actual, (int, float)) and not isinstance(actual, bool):
        return abs(shown - actual) <= 1e-12 * max(abs(shown), abs(actual))
    return shown == actual


def json_matches(shown_lines, actual_text):
    """Each '"key": value' line shown must equal the actual JSON's value for that key."""
    try:
        actual = json.loads(actual_text[actual_text.index("{"):])
    except (ValueError, json.JSONDecodeError) as e:
        return f"output is not JSON: {e}"
    for line in shown_lines:
        m = re.match(r'^\s*"(\w+)": (.*?),?\s*$', line)
        if not m:
            continue
        key, value = m.group(1), m.group(2)
        if key not in actual:
            return f"key {key} is not in the output"
        if "..." in value:
            items = [v.strip() for v in value.strip("[]").split(",") if v.strip() not in ("", "...")]
            want = [json.loads(v) for v in items]
            if not same_value(want, actual[key][: len(want)]):
                return f"{key}: shown {want}, got {actual[key][:len(want)]}"
            continue
        if not same_value(json.loads(value), actual[key]):
            return f"{key}: shown {value}, got {json.dumps(actual[key])}"
    return None


def run(command, cwd, env):
    p = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True,
                       timeout=600)
    return p.returncode, p.stdout + p.stderr


def main():
    *docs, build, source = sys.argv[1:]
    text = "\n".join(open(d, encoding="utf-8").read() for d in docs)
    work = tempfile.mkdtemp(prefix="spectralize_readme_")
    env = dict(os.environ)
    env.pop("OCIO", None)
    failures, checked = [], 0
    try:
        os.symlink(os.path.abspath(build), os.path.join(work, "build"))
        for name in ("testimages", "ocio_configs", "tests"):
            os.symlink(os.path.join(os.path.abspath(source), name), os.path.join(work, name))
        env_py = dict(env, PYTHONPATH=os.path.join(work, "build", "python"), MPLBACKEND="Agg")
        found = blocks(text)
        for index, (kind, lines) in enumerate(found):
            if kind == "text":
                continue
            if kind == "python":
                p = subprocess.run([sys.executable, "-c", "\n".join(lines)], cwd=work, env=env_py,
                                   capture_output=True, text=True, timeout=600)
                checked += 1
                if p.returncode != 0:
                    failures.append(f"python block failed ({p.returncode}):\n{p.stderr[-3000:]}")
                elif index + 1 < len(found) and found[index + 1][0] == "text":
                    shown = [l for l in found[index + 1][1] if l.strip()]
                    why = lines_match(shown, [l for l in p.stdout.split("\n") if l.strip()])
                    if why:
                        failures.append(f"python block: {why}\n--- output:\n{p.stdout}")
                continue
            if kind == "sh":
                if any(l.strip().startswith("make ") for l in lines):
                    continue
                script = "set -e\n" + "\n".join(lines)
                code, out = run(script, work, env)
                checked += 1
                if code != 0:
                    failures.append(f"sh block failed ({code}):\n{script}\n--- output:\n{out}")
                continue
            # "$ command" blocks.
            i = 0
            while i < len(lines):
                if not lines[i].startswith("$ "):
                    i += 1
                    continue
                command = lines[i][2:]
                j = i + 1
                while j < len(lines) and not lines[j].startswith("$ "):
                    j += 1
                shown = [l for l in lines[i + 1:j] if l.strip()]
                code, out = run(command, work, env)
                checked += 1
                if code != 0:
                    failures.append(f"$ {command}\nexit {code}:\n{out}")
                elif shown and shown[0].lstrip().startswith("{"):
                    why = json_matches(shown, out)
                    if why:
                        failures.append(f"$ {command}\n{why}")
                elif shown:
                    why = lines_match(shown, [l for l in out.split("\n") if l.strip()])
                    if why:
                        failures.append(f"$ {command}\n{why}\n--- output:\n{out}")
                i = j
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print("FAILED:", f, "\n", file=sys.stderr)
    print(f"{checked} examples run, {len(failures)} failed")
    return 1 if failures or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
