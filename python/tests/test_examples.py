"""The Python examples run (headless matplotlib) and write their pictures."""
import os
import subprocess
import sys

from conftest import SOURCE_DIR

# Generous: under the sanitizers on a loaded 2-core machine the fit example took more than 120 s;
# a hang is still ended by the ctest entry's own TIMEOUT (python/CMakeLists.txt).
TIMEOUT_S = 600


def test_polar_lobes_example_writes_a_png(tmp):
    out = tmp / "lobes.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, str(SOURCE_DIR / "examples/python/polar_lobes.py"), "-o", str(out)],
                       capture_output=True, text=True, env=env, timeout=TIMEOUT_S)
    assert p.returncode == 0, p.stderr
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_fit_cornell_example_writes_a_png(tmp):
    # A quick configuration (one model, two starts); the docs' picture uses the defaults.
    out = tmp / "fit.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, str(SOURCE_DIR / "examples/python/fit_cornell.py"),
                        str(SOURCE_DIR / "data/measured/cornell/cayman.brdf"), "--model", "ggx", "--starts", "2",
                        "-o", str(out)], capture_output=True, text=True, env=env, timeout=TIMEOUT_S)
    assert p.returncode == 0, p.stderr
    assert "ggx: l2cos" in p.stdout
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
