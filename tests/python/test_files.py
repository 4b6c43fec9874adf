"""spectralize.convert() and ingest(): the CLI's jobs from Python, with its reports and errors."""
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import OpenImageIO as oiio
import pytest

from conftest import IMAGES, relative_error


def read(path):
    buf = oiio.ImageBuf(str(path))
    assert not buf.has_error, buf.geterror()
    return buf.spec(), buf.get_pixels(oiio.FLOAT)


def test_convert_writes_the_spectral_layout_and_returns_the_report(sp, tmp_path, oracle):
    out = tmp_path / "forest.exr"
    report = sp.convert(IMAGES / "hdri_forest_256x128.exr", out, format="float")
    assert report["output"] == str(out) and report["width"] == 256 and report["height"] == 128
    assert report["mode"] == "emission" and report["format"] == "float"
    assert report["max_relative_xyz_error"] <= 1e-5
    spec, pixels = read(out)
    names = list(spec.channelnames)
    # The spectral layout of Fichet et al. (docs/DESIGN.md §7): "S0.<nm with a comma>nm".
    assert names[:3] == ["R", "G", "B"]
    assert names[3] == "S0.380,000000nm" and names[-1] == "S0.780,000000nm"
    # Every pixel's spectrum reproduces the input's colour (independent integration).
    _, rgb = read(IMAGES / "hdri_forest_256x128.exr")
    wl = np.arange(380, 781, 5.0)
    xyz = oracle.emission_xyz(pixels[:, :, 3:].reshape(-1, 81), wl)
    target = oracle.xyz_of_rgb(rgb[:, :, :3].reshape(-1, 3))
    keep = np.abs(target).max(axis=1) > 1e-3
    assert relative_error(xyz[keep], target[keep]) <= 1e-5


def test_convert_back_to_rgb(sp, tmp_path):
    spectral = tmp_path / "s.exr"
    sp.convert(IMAGES / "sweep_rec2020_64x32.exr", spectral, format="float",
               colorspace="Linear Rec.2020")
    back = tmp_path / "back.exr"
    report = sp.convert(spectral, back, to="rgb", colorspace="Linear Rec.2020")
    assert report["colorspace"] == "Linear Rec.2020"
    _, a = read(IMAGES / "sweep_rec2020_64x32.exr")
    _, b = read(back)
    # Out-of-gamut pixels of the sweep are mapped: compare the in-gamut ones (all positive).
    inside = (a[:, :, :3] > 0.01).all(axis=2)
    assert np.abs(b[inside][:, :3] - a[inside][:, :3]).max() <= 1e-3 * a.max()


def test_messages_name_the_options_as_python_spells_them(sp, tmp_path):
    # A light brighter than HALF holds (65504): the warning advises the keyword, not the flag.
    src = tmp_path / "bright.exr"
    buf = oiio.ImageBuf(oiio.ImageSpec(4, 2, 3, oiio.FLOAT))
    oiio.ImageBufAlgo.fill(buf, (1e6, 2e6, 1e6))
    assert buf.write(str(src)), buf.geterror()
    with pytest.warns(sp.SpectralizeWarning) as caught:
        sp.convert(src, tmp_path / "out.exr", mode="emission")
    text = " ".join(str(w.message) for w in caught)
    assert "use format float to keep them" in text, text
    assert "--format" not in text, text
    # The same through ingest().
    lib = tmp_path / "lib"
    lib.mkdir()
    os.link(src, lib / "bright.exr")
    with pytest.warns(sp.SpectralizeWarning) as caught:
        sp.ingest([lib], output=tmp_path / "done", mode="emission")
    text = " ".join(str(w.message) for w in caught)
    assert "--format" not in text, text


def test_convert_refuses_bad_options_before_any_work(sp, tmp_path):
    src = IMAGES / "hdri_forest_256x128.exr"
    with pytest.raises(ValueError, match=r"convert\(\): output '.*x.png': the output is a spectral OpenEXR"):
        sp.convert(src, tmp_path / "x.png")
    with pytest.raises(ValueError, match=r"convert\(\): colorspace: unknown colour space 'nope'"):
        sp.convert(src, tmp_path / "x.exr", colorspace="nope")
    with pytest.raises(ValueError, match=r"convert\(\): unknown option 'colour_space'"):
        sp.convert(src, tmp_path / "x.exr", colour_space="ACEScg")
    with pytest.raises(ValueError, match=r"to 'xyz' \(valid: spectral, rgb\)"):
        sp.convert(src, tmp_path / "x.exr", to="xyz")
    with pytest.raises(ValueError, match=r"give colorspace or display, not both"):
        sp.convert(src, tmp_path / "x.exr", to="rgb", colorspace="ACEScg", display="sRGB - Display")
    with pytest.raises(TypeError, match=r"input: expected a path"):
        sp.convert(3, tmp_path / "x.exr")
    assert list(tmp_path.iterdir()) == []


def test_convert_file_problems_are_oserrors_and_leave_nothing(sp, tmp_path):
    with pytest.raises(OSError, match=r"missing.png"):
        sp.convert(tmp_path / "missing.png", tmp_path / "x.exr")
    truncated = tmp_path / "cut.exr"
    truncated.write_bytes((IMAGES / "hdri_forest_256x128.exr").read_bytes()[:3000])
    with pytest.raises(OSError, match=r"cut.exr"):
        sp.convert(truncated, tmp_path / "x.exr")
    with pytest.raises(OSError, match=r"not a spectral|no spectral channels"):
        sp.convert(IMAGES / "hdri_forest_256x128.exr", tmp_path / "y.exr", to="rgb")
    # The input is never overwritten, under any name.
    src = tmp_path / "in.exr"
    src.write_bytes((IMAGES / "hdri_forest_256x128.exr").read_bytes())
    before = src.read_bytes()
    with pytest.raises(OSError):
        sp.convert(src, tmp_path / "." / "in.exr")
    assert src.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cut.exr", "in.exr"]


def test_keyboard_interrupt_stops_convert_and_removes_the_temporary(tmp_path):
    """SIGINT during a long conversion raises KeyboardInterrupt; no output, no temporary."""
    script = f"""
import os, signal, threading, spectralize
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    spectralize.convert({str(IMAGES / 'hdri_interior_1024x512.exr')!r}, {str(tmp_path / 'o.exr')!r},
                        wavelengths='360:830:1', format='float', threads=1)
    print('finished')
except KeyboardInterrupt:
    print('interrupted')
"""
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert p.stdout.strip() == "interrupted", p.stdout + p.stderr
    assert list(tmp_path.iterdir()) == []


def test_ingest_a_folder(sp, tmp_path):
    lib = tmp_path / "lib"
    (lib / "wood").mkdir(parents=True)
    (lib / "wood" / "oak_albedo.png").write_bytes((IMAGES / "colorchecker_srgb8.png").read_bytes())
    (lib / "wood" / "oak_normal.png").write_bytes((IMAGES / "grey_ramp8.png").read_bytes())
    (lib / "sky_hdri.exr").write_bytes((IMAGES / "hdri_sunset_256x128.exr").read_bytes())
    out = tmp_path / "out"
    s = sp.ingest(lib, out)
    assert (s["files"], s["converted"], s["skipped_data"], s["failed"]) == (3, 2, 1, 0)
    assert (out / "wood" / "oak_albedo.exr").exists() and (out / "sky_hdri.exr").exists()
    assert sp.ingest([lib], out)["up_to_date"] == 2
    with pytest.raises(ValueError, match=r"ingest\(\): unknown option 'jobz'"):
        sp.ingest(lib, out, jobz=2)
    with pytest.raises(ValueError, match=r"shard '3/2'"):
        sp.ingest(lib, out, shard="3/2")
    # A missing source fails like any file (the batch goes on), named in the result.
    with pytest.warns(sp.SpectralizeWarning, match=r"1 of 1 files failed"):
        s = sp.ingest(tmp_path / "nowhere", tmp_path / "out2")
    assert s["failed"] == 1 and "no such file" in s["failures"][0]["message"]
    assert s["failures"][0]["input"] == str(tmp_path / "nowhere")


def test_table_is_the_cli_table_byte_for_byte(sp, tmp_path):
    """table() writes what `spectralize table` writes for the same settings, and refuses what
    the CLI refuses (an encoded space is named with its linear twin)."""
    exe = os.environ["SPECTRALIZE_EXE"]
    ours, theirs = tmp_path / "py.spztab", tmp_path / "cli.spztab"
    summary = sp.table(ours, colorspace="Linear Rec.2020", mode="emission", wavelengths="400:700:10")
    subprocess.run([exe, "table", "-o", str(theirs), "--colorspace", "Linear Rec.2020",
                    "--mode", "emission", "--wavelengths", "400:700:10", "-q"], check=True)
    assert ours.read_bytes() == theirs.read_bytes()
    assert summary["colorspace"] == "Linear Rec.2020" and summary["mode"] == "emission"
    assert summary["bytes"] == ours.stat().st_size and summary["spectra"] > 100
    with pytest.raises(ValueError, match="Linear Rec.709"):
        sp.table(tmp_path / "x.spztab", colorspace="sRGB - Texture")
    with pytest.raises(ValueError, match="spztab"):
        sp.table(tmp_path / "x.exr")
    with pytest.raises(ValueError, match="method"):
        sp.table(tmp_path / "x.spztab", method="exact")
    assert not (tmp_path / "x.spztab").exists()
