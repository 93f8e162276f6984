"""Shared helpers of the Python tests (run by ctest: python/CMakeLists.txt sets the environment).

Run by hand from the repository root after `make build`:
    PYTHONPATH=build/release/python ANISO_CLI=build/release/bin/aniso \\
    ANISO_BATCH_EVAL_CPP=build/release/bin/aniso_batch_eval_cpp /usr/bin/python3 -m pytest python/tests
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ANISO_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("ANISO_CLI", str(SOURCE_DIR / "build/release/bin/aniso"))
BATCH_EVAL_CPP = os.environ.get("ANISO_BATCH_EVAL_CPP", str(SOURCE_DIR / "build/release/bin/aniso_batch_eval_cpp"))


def native_env():
    """The environment for the aniso executables (the CLI, aniso_batch_eval_cpp). In the sanitizer
    build ctest preloads the ASan runtime into this interpreter (python/CMakeLists.txt); the
    executables link their own, and ASan refuses a second runtime in one process, so they start
    without the preload. Elsewhere: this environment unchanged."""
    env = dict(os.environ)
    preload = env.get("ANISO_SANITIZER_PRELOAD")
    if preload and env.get("LD_PRELOAD") == preload:
        del env["LD_PRELOAD"]
    return env


def run_cli(*args, stdin=""):
    """Runs the CLI; returns (exit status, stdout, stderr)."""
    p = subprocess.run([CLI, *args], input=stdin, capture_output=True, text=True, timeout=120, env=native_env())
    return p.returncode, p.stdout, p.stderr


def cli_error(*args, stdin=""):
    """The CLI's error message for a failing command, without the "aniso: error: " prefix."""
    rc, out, err = run_cli(*args, stdin=stdin)
    assert rc == 2, (rc, out, err)
    assert out == ""
    prefix = "aniso: error: "
    assert err.startswith(prefix), err
    return err[len(prefix):].rstrip("\n")


def random_pairs(n, seed, grazing=False):
    """n pairs of unit directions above the horizon, (n, 3) float64 each: uniform on the
    hemisphere, plus (grazing) some at cosines down to 1e-4."""
    rng = np.random.default_rng(seed)

    def hemisphere(k):
        v = rng.normal(size=(k, 3))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        v[:, 2] = np.abs(v[:, 2]) + 1e-3
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    wi, wo = hemisphere(n), hemisphere(n)
    if grazing:
        k = n // 8
        cz = 10.0 ** rng.uniform(-4, -2, size=k)
        phi = rng.uniform(0, 2 * np.pi, size=k)
        s = np.sqrt(1 - cz * cz)
        wi[:k] = np.stack([s * np.cos(phi), s * np.sin(phi), cz], axis=1)
    return wi, wo


@pytest.fixture
def tmp(tmp_path):
    return tmp_path
