#!/usr/bin/env python3
"""make docs-renders: writes the path tracer's numbers (OUTDIR/convergence.json,
OUTDIR/compare_A.json, OUTDIR/compare_D65.json, from cmake/renders.sh) into docs/RENDERERS.md,
between its `<!-- renders: NAME -->` and `<!-- end renders -->` lines. Numbers have 3
significant digits, as the Slow path tracer test compares them.
Usage: render_tables.py OUTDIR DOC.md"""
import json
import os
import re
import sys


def g3(v):
    return "%.3g" % v


def convergence(out):
    d = json.load(open(os.path.join(out, "convergence.json")))
    rows = ["| spp | mean ΔE2000 | p95 | max | previous mean ÷ mean |", "|---:|---:|---:|---:|---:|"]
    previous = None
    for p in d["convergence"]:
        s = p["rt_vs_reference"]
        ratio = "–" if previous is None else "%.2f" % (previous / s["mean"])
        previous = s["mean"]
        rows.append(f"| {p['spp']} | {g3(s['mean'])} | {g3(s['p95'])} | {g3(s['max'])} | {ratio} |")
    f = d["floor"]
    rows.append(f"| all 471 wavelengths | {g3(f['mean'])} | {g3(f['p95'])} | {g3(f['max'])} | – |")
    return rows


def comparison(out):
    rows = ["| light | spectralize::rt mean ΔE2000 | p95 | Jakob & Hanika 64³ mean ΔE2000 | p95 |",
            "|---|---:|---:|---:|---:|"]
    for light in ("A", "D65"):
        d = json.load(open(os.path.join(out, f"compare_{light}.json")))
        r, b = d["rt_vs_truth"], d["baseline_vs_truth"]
        rows.append(f"| {light} | {g3(r['mean'])} | {g3(r['p95'])} | {g3(b['mean'])} | {g3(b['p95'])} |")
    return rows


def main():
    out, doc = sys.argv[1], sys.argv[2]
    text = open(doc, encoding="utf-8").read()
    for name, rows in (("convergence", convergence(out)), ("comparison", comparison(out))):
        pattern = re.compile(rf"(<!-- renders: {name} -->\n).*?(<!-- end renders -->)", re.S)
        if not pattern.search(text):
            sys.exit(f"{doc}: no '<!-- renders: {name} -->' ... '<!-- end renders -->' block")
        text = pattern.sub(lambda m: m.group(1) + "\n".join(rows) + "\n" + m.group(2), text)
    open(doc, "w", encoding="utf-8").write(text)


if __name__ == "__main__":
    main()
