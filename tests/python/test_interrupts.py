"""Ctrl-C during spectra(), convert() and ingest() is heard within a second: KeyboardInterrupt,
no half-done output presented as done, and for ingest() the summary and the manifest of what
was done. Results never depend on reading a stream back (manifest="/dev/stdout")."""
import json
import pathlib
import subprocess
import sys

import pytest

from conftest import IMAGES

# A child interpreter sends itself SIGINT once TRIGGER returns (on a watcher thread) and prints,
# as JSON, how long the call went on after the signal and what it raised.
HARNESS = r"""
import json, os, pathlib, signal, threading, time, warnings, numpy as np, spectralize
warnings.simplefilter("ignore")
sent = []
def interrupt():
    TRIGGER
    sent.append(time.monotonic())
    os.kill(os.getpid(), signal.SIGINT)
result = {}
threading.Thread(target=interrupt, daemon=True).start()
start = time.monotonic()
try:
    CALL
    result["raised"] = None
except KeyboardInterrupt as e:
    result["raised"] = "KeyboardInterrupt"
    result["summary"] = getattr(e, "summary", None)
    result["message"] = str(e)
end = time.monotonic()
result["after_signal"] = end - sent[0] if sent else None
print(json.dumps(result))
"""


def run_interrupted(call, trigger, cwd):
    script = HARNESS.replace("TRIGGER", trigger).replace("CALL", call)
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=300, cwd=cwd)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_spectra_stops_within_a_second(tmp_path):
    """Reproduction: the interrupt was only seen when the whole call ended. ~3 s of direct
    solves (method='exact' on one core) interrupted at 0.3 s."""
    call = ("rgb = np.random.default_rng(1).uniform(0.05, 0.9, (40000, 3))\n"
            "    out = np.zeros((40000, 81), np.float32)\n"
            "    spectralize.spectra(rgb, out=out, mode='reflectance', method='exact', threads=1)")
    r = run_interrupted(call, "time.sleep(0.3)", tmp_path)
    assert r["raised"] == "KeyboardInterrupt", r
    assert r["after_signal"] < 1.0, r


def test_convert_stops_within_a_second_leaving_nothing(tmp_path):
    """Seconds of direct solves of 471 bands on one core, interrupted once the conversion runs
    (its temporary file holds the header: the solver's setup, which is not interruptible, is
    done; 0.25 s of CPU, 1.5 s under load)."""
    call = (f"spectralize.convert({str(IMAGES / 'hdri_interior_1024x512.exr')!r}, 'o.exr', "
            "wavelengths='360:830:1', format='float', method='exact', threads=1, "
            "compression='none')")
    trigger = ("while not [p for p in pathlib.Path('.').iterdir()\n"
               "               if '.spectralize-' in p.name and p.stat().st_size > 0]:\n"
               "        time.sleep(0.01)\n"
               "    time.sleep(0.2)")
    r = run_interrupted(call, trigger, tmp_path)
    assert r["raised"] == "KeyboardInterrupt", r
    assert r["after_signal"] < 1.0, r
    assert list(tmp_path.iterdir()) == []


def test_ingest_stops_within_a_second_and_reports_what_was_done(tmp_path):
    """Reproduction: the interrupt was seen at the end and the result was lost. Oracle: the
    files on disk and the manifest."""
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
               "        time.sleep(0.01)")
    r = run_interrupted(call, trigger, tmp_path)
    assert r["raised"] == "KeyboardInterrupt", r
    assert r["after_signal"] < 1.0, r
    summary = r["summary"]
    assert summary is not None and summary["interrupted"] is True, r
    out = tmp_path / "out"
    done = sorted(p.name for p in out.iterdir() if p.suffix == ".exr")
    assert summary["converted"] == len(done) >= 1
    assert summary["not_done"] == 4 - len(done) >= 1
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
