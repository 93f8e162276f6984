"""The Python examples run (headless matplotlib) and write their pictures."""
import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_polar_lobes_example_writes_a_png(tmp):
    out = tmp / "lobes.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, str(SOURCE_DIR / "examples/python/polar_lobes.py"), "-o", str(out)],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
