#!/usr/bin/env python3
"""spectralize.spectra() from Python against the same colours through the C++ path, in one run
(make bench): 1,000,000 random Linear Rec.709 colours (seeded) at 5 nm, warm table, median of
RUNS calls each (as light); then 1,000,000 colours with a channel above 0.95 as light and as
reflectances (cells at the reflectance solid's boundary, blended without solves).
Prints Mcolour/s for each and the ratios Python / C++. python_spectra returns a new array per
call (its pages are faulted in: ~0.3 GB at 1M x 81); python_spectra_out fills one given with
out=, as the C++ loop reuses its buffer.

Usage: bench_python.py BUILD_DIR [RUNS] [COLOURS]"""
import os
import subprocess
import sys
import tempfile
import time

build = sys.argv[1] if len(sys.argv) > 1 else "build"
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 5
count = int(sys.argv[3]) if len(sys.argv) > 3 else 1_000_000
sys.path.insert(0, os.path.join(build, "python"))
import numpy as np  # noqa: E402
import spectralize  # noqa: E402


def measure(label, rgb, mode="emission"):
    with tempfile.NamedTemporaryFile(suffix=".f32") as f:
        rgb.tofile(f.name)
        cpp = subprocess.run([os.path.join(build, "tests", "bench", "bench_colour_arrays"),
                              f.name, str(runs), mode], capture_output=True, text=True,
                             check=True).stdout
    spectralize.spectra(rgb, mode=mode)  # warm: every node these colours need
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        spectralize.spectra(rgb, mode=mode)
        times.append(time.perf_counter() - t0)
    py_s = sorted(times)[len(times) // 2]
    out = np.empty(rgb.shape[:-1] + (81,), dtype=np.float32)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        spectralize.spectra(rgb, out=out, mode=mode)
        times.append(time.perf_counter() - t0)
    py_out_s = sorted(times)[len(times) // 2]
    rates = {}
    for line in cpp.strip().split("\n"):
        name, n, seconds = line.split()
        rates[name] = int(n) / float(seconds) / 1e6
    rates["python_spectra"] = len(rgb) / py_s / 1e6
    rates["python_spectra_out"] = len(rgb) / py_out_s / 1e6
    print(f"== {label}, {mode}")
    for name, rate in rates.items():
        print(f"{name:26s} {rate:7.2f} Mcolour/s")
    for name in ("python_spectra", "python_spectra_out"):
        ratio = rates[name] / rates["cpp_colour_arrays"]
        print(f"{name} / cpp_colour_arrays (same colours, same run): {ratio:.2f}x")


rng = np.random.default_rng(1)
measure("random colours in the unit cube",
        rng.uniform(0.0, 1.0, size=(count, 3)).astype(np.float32))
bright = rng.uniform(0.0, 1.0, size=(8 * count, 3)).astype(np.float32)
bright = bright[bright.max(axis=1) > 0.95][:count]
for mode in ("emission", "reflectance"):
    measure("random colours with a channel above 0.95", bright, mode)
