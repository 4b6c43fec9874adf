"""ingest(shard=...) and `spectralize ingest --shard` share one parser (ingest/shard.h): the same
specs are refused by both, before any work."""
import os
import subprocess

import pytest

from conftest import IMAGES

SPECS_REFUSED = ["0/1e3", "0/2x", "0/2/3", "-1/2", "01/2", "0/0", " 0/2", "2/2", "0/", "/2",
                 "0/99999999999999999999", "1"]


@pytest.mark.parametrize("spec", SPECS_REFUSED)
def test_python_refuses_what_the_cli_refuses(sp, tmp_path, spec):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "a.png").write_bytes((IMAGES / "grey_ramp8.png").read_bytes())
    cli = subprocess.run([os.environ["SPECTRALIZE_EXE"], "ingest", str(lib), "-o",
                          str(tmp_path / "cli"), "--shard", spec], capture_output=True, text=True)
    assert cli.returncode == 2, cli.stderr
    with pytest.raises(ValueError, match=r"ingest\(\): shard"):
        sp.ingest(lib, tmp_path / "py", shard=spec)
    assert not (tmp_path / "py").exists() and not (tmp_path / "cli").exists()


def test_python_accepts_what_the_cli_accepts(sp, tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "a.png").write_bytes((IMAGES / "grey_ramp8.png").read_bytes())
    s = sp.ingest(lib, tmp_path / "out", shard="0/1")
    assert (s["files"], s["failed"]) == (1, 0)
