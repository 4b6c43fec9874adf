"""Ctrl-C during spectra(), convert() and ingest() is heard while the work goes on, not at its
end: KeyboardInterrupt, no half-done output presented as done, and for ingest() the summary and
the manifest of what was done. Results never depend on reading a stream back
(manifest="/dev/stdout"). What the call did after the signal is counted (rows written, bytes
written, files converted), never timed: a loaded machine slows both sides alike."""
import json
import pathlib
import subprocess
import sys

import pytest

from conftest import IMAGES

# A child interpreter runs SETUP, then CALL while a watcher thread waits for TRIGGER, notes
# MEASURE, sends the process SIGINT and goes on noting MEASURE's largest value until the call
# returns; it prints, as JSON, what the call raised and MEASURE at the signal and at the end.
HARNESS = r"""
import json, os, pathlib, signal, threading, time, warnings, numpy as np, spectralize
warnings.simplefilter("ignore")
SETUP
def measure():
    return MEASURE
result = {"at_signal": None, "largest": None}
returned = threading.Event()
def interrupt():
    TRIGGER
    result["at_signal"] = result["largest"] = measure()
    os.kill(os.getpid(), signal.SIGINT)
    while not returned.is_set():
        result["largest"] = max(result["largest"], measure())
        time.sleep(0.001)
threading.Thread(target=interrupt, daemon=True).start()
try:
    CALL
    result["raised"] = None
except KeyboardInterrupt as e:
    result["raised"] = "KeyboardInterrupt"
    result["summary"] = getattr(e, "summary", None)
    result["message"] = str(e)
returned.set()
result["at_end"] = measure()
print(json.dumps(result))
"""


def run_interrupted(call, trigger, cwd, setup="", measure="0"):
    script = (HARNESS.replace("SETUP", setup).replace("TRIGGER", trigger)
              .replace("MEASURE", measure).replace("CALL", call))
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=300, cwd=cwd)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_spectra_stops_at_its_next_piece():
    """Reproduction: the interrupt was only seen when the whole call ended. ~3 s of direct
    solves (method='exact' on one core) interrupted once a tenth of the rows are written: the
    rows written after the signal are the pieces in flight (a piece is ~0.1 s of work, sized
    from the last one's time), far fewer than before it, and far from all."""
    setup = ("rgb = np.random.default_rng(1).uniform(0.05, 0.9, (40000, 3))\n"
             "out = np.zeros((40000, 81), np.float32)")
    call = "spectralize.spectra(rgb, out=out, mode='reflectance', method='exact', threads=1)"
    measure = "int(np.count_nonzero(out.any(axis=1)))"
    trigger = ("while measure() < 4000:\n"
               "        time.sleep(0.001)")
    r = run_interrupted(call, trigger, None, setup, measure)
    assert r["raised"] == "KeyboardInterrupt", r
    assert r["at_signal"] >= 4000, r
    assert r["at_end"] - r["at_signal"] <= r["at_signal"], r
    assert r["at_end"] < 40000, r


def test_convert_stops_before_its_end_leaving_nothing(tmp_path):
    """Seconds of direct solves of 471 bands on one core, interrupted once the conversion runs
    (its temporary file holds the header: the solver's setup, which is not interruptible, is
    done): the temporary never holds the image (1024 x 512 x 474 float samples) and is
    removed."""
    call = (f"spectralize.convert({str(IMAGES / 'hdri_interior_1024x512.exr')!r}, 'o.exr', "
            "wavelengths='360:830:1', format='float', method='exact', threads=1, "
            "compression='none')")
    measure = ("sum(p.stat().st_size for p in pathlib.Path('.').iterdir()\n"
               "           if '.spectralize-' in p.name and p.exists())")
    trigger = ("while not measure():\n"
               "        time.sleep(0.001)")
    r = run_interrupted(call, trigger, tmp_path, measure=measure)
    assert r["raised"] == "KeyboardInterrupt", r
    assert 0 < r["largest"] < 1024 * 512 * 474 * 4, r
    assert list(tmp_path.iterdir()) == []


def test_ingest_stops_in_the_file_it_converts_and_reports_what_was_done(tmp_path):
    """Reproduction: the interrupt was seen at the end and the result was lost. Oracle: the
    files on disk and the manifest. The signal comes once the first (small) file is written:
    the one in progress is abandoned and none is started after, whatever the machine's load."""
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "a_hdri.exr").write_bytes((IMAGES / "hdri_sunset_256x128.exr").read_bytes())
    big = (IMAGES / "hdri_interior_1024x512.exr").read_bytes()
    for name in ("b_hdri.exr", "c_hdri.exr", "d_hdri.exr"):
        (lib / name).write_bytes(big)
    # One file at a time, the small one first; the signal once its output exists.
    call = ("spectralize.ingest('lib', 'out', jobs=1, threads=1, method='exact', "
            "wavelengths='380:780:10', compression='none')")
    trigger = ("while not list(pathlib.Path('out').glob('*.exr')):\n"
               "        time.sleep(0.001)")
    r = run_interrupted(call, trigger, tmp_path)
    assert r["raised"] == "KeyboardInterrupt", r
    summary = r["summary"]
    assert summary is not None and summary["interrupted"] is True, r
    out = tmp_path / "out"
    done = sorted(p.name for p in out.iterdir() if p.suffix == ".exr")
    assert done == ["a_hdri.exr"], done  # b (seconds of solves) abandoned, c and d not started
    assert summary["converted"] == 1 and summary["not_done"] == 3, summary
    assert "interrupted" in r["message"] and "not done" in r["message"]
    records = [json.loads(line)
               for line in (out / "spectralize-ingest.jsonl").read_text().splitlines()]
    assert [x["summary"]["interrupted"] for x in records if "summary" in x] == [True]
    assert sorted(pathlib.Path(x["output"]).name for x in records if "output" in x) == done
    assert not [p for p in out.iterdir() if ".spectralize-" in p.name]


def test_ingest_to_a_stream_manifest_returns_its_failures(tmp_path):
    """Reproduction: manifest='/dev/stdout' with a failing file hung (the stream was opened
    again to read the failures back). The result comes from memory."""
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "ok_hdri.exr").write_bytes((IMAGES / "hdri_sunset_256x128.exr").read_bytes())
    (lib / "broken.png").write_bytes(b"not a png at all")
    script = ("import json, warnings, spectralize\n"
              "warnings.simplefilter('ignore')\n"
              "s = spectralize.ingest('lib', 'out', manifest='/dev/stdout')\n"
              "print('RESULT', json.dumps(s))\n")
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=60, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    result = json.loads(next(line for line in lines if line.startswith("RESULT "))[7:])
    assert (result["converted"], result["failed"]) == (1, 1)
    assert len(result["failures"]) == 1 and result["failures"][0]["input"].endswith("broken.png")
    # The manifest went to the stream: the same failure record is there.
    records = [json.loads(line) for line in lines if line.startswith("{")]
    assert [r for r in records if r.get("status") == "failed"] == result["failures"]
