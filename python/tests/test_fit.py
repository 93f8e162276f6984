"""aniso.fit: the CLI's fitter from Python (docs/python.md, docs/fitting.md).

The fitted material and its error figures equal `aniso fit`'s for the same data, options and seed
(a Cornell file and a CSV); parameters are recovered from synthetic arrays; bad data and options
raise ValueError with the CLI's message; progress callbacks, Ctrl-C and the released GIL."""
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import aniso
from conftest import SOURCE_DIR, cli_error, run_cli

KRYLON = str(SOURCE_DIR / "data/measured/cornell/krylon_blue.brdf")


def cli_fit(tmp, data, *args):
    out = tmp / "fitted.json"
    rc, stdout, stderr = run_cli("fit", data, *args, "-q", "-o", str(out))
    assert rc == 0, stderr
    return json.loads(out.read_text()), stdout


def without_seconds(d):
    d = json.loads(json.dumps(d))
    d["fit"].pop("seconds")
    return d


def test_fit_of_an_rgl_file_equals_the_cli_and_read_measured_says_what_was_sampled(tmp):
    # An isotropic GGX written as an RGL tensor file (aniso export-rgl, docs/rgl.md), then fitted as
    # data (docs/fitting.md): the file's table sampled on a grid of directions.
    path = tmp / "ggx.bsdf"
    rc, _, stderr = run_cli("export-rgl", "--material", '{"model": "ggx", "kd": 0.1, "f0": 0.5, "alpha": 0.2}', "--rgb",
                            "-o", str(path))
    assert rc == 0, stderr
    d = aniso.read_measured(path)
    assert d["format"] == "rgl"
    assert "isotropic" in d["description"] and "half/difference-angle grid" in d["description"]
    assert d["wi"].shape == d["value"].shape == (len(d["weight"]), 3)
    fitted, stdout = cli_fit(tmp, str(path), "--model", "ggx", "--starts", "1")
    assert "sampled: RGL tensor file" in stdout
    r = aniso.fit(path, model="ggx", starts=1, progress=False)
    assert without_seconds(r.to_dict()) == without_seconds(fitted)
    assert r.to_dict()["fit"]["sampled"] == d["description"]
    assert not r.to_dict()["fit"]["anisotropic"]
    assert abs(r.to_dict()["alpha_x"] - 0.2) < 0.01


def test_grid_sets_an_rgl_files_sampling_as_the_clis_grid(tmp):
    # grid=N as `aniso fit --grid N`: N theta_h x N/2 theta_d x N phi_d for a .bsdf file; refused,
    # with the CLI's message, for data that have samples of their own, for odd or out-of-range N
    # and for the arrays.
    path = tmp / "ggx.bsdf"
    rc, _, stderr = run_cli("export-rgl", "--material", '{"model": "ggx", "kd": 0.1, "f0": 0.5, "alpha": 0.2}', "--rgb",
                            "-o", str(path))
    assert rc == 0, stderr
    d = aniso.read_measured(path, grid=8)
    assert "8 theta_h (square-root spaced) x 4 theta_d x 8 phi_d" in d["description"]
    assert len(d["weight"]) < len(aniso.read_measured(path)["weight"])
    fitted, _ = cli_fit(tmp, str(path), "--model", "ggx", "--starts", "1", "--grid", "8")
    r = aniso.fit(path, model="ggx", starts=1, progress=False, grid=8)
    assert without_seconds(r.to_dict()) == without_seconds(fitted)
    with pytest.raises(ValueError, match="grid applies to an RGL tensor file"):
        aniso.fit(KRYLON, model="ggx", grid=8)
    for bad in (7, 2, 258):
        with pytest.raises(ValueError, match="grid: expected an even number"):
            aniso.read_measured(path, grid=bad)
    with pytest.raises(ValueError, match="grid: expected an integer"):
        aniso.fit(path, model="ggx", grid=8.0)
    with pytest.raises(ValueError, match="not to the arrays"):
        aniso.fit(wi=d["wi"], wo=d["wo"], value=d["value"], model="ggx", grid=8)


def test_fit_of_a_cornell_file_equals_the_cli(tmp):
    fitted, stdout = cli_fit(tmp, KRYLON, "--model", "ward", "--normalization", "duer", "--starts", "4", "--seed", "7")
    r = aniso.fit(KRYLON, model="ward", normalization="duer", starts=4, seed=7, progress=False)
    # Everything but the time: the material's numbers, the errors, the best start, the iterations.
    assert without_seconds(r.to_dict()) == without_seconds(fitted)
    assert r.material == aniso.Material(str(tmp / "fitted.json"))
    m, errors = r
    assert m == r.material and errors == fitted["fit"]["error"]
    assert set(errors) == {"l2cos", "l2cos_rgb", "log", "log_rgb", "relative_l2cos"}
    # The CLI's error table prints the same figures (5 significant digits).
    row = next(line for line in stdout.splitlines() if line.startswith("l2cos (Ngan 2005)")).split()[-4:]
    assert [float(x) for x in row] == pytest.approx(errors["l2cos_rgb"] + [errors["l2cos"]], rel=1e-4)
    assert r.samples == fitted["fit"]["samples"] and r.best_start == fitted["fit"]["best_start"]
    assert list(r.parameters) == ["kd.r", "kd.g", "kd.b", "ks.r", "ks.g", "ks.b", "alpha"]


def test_fit_of_a_csv_with_the_log_metric_equals_the_cli(tmp):
    # A CSV of samples (degrees) from an anisotropic GGX material, fitted anisotropically with the
    # log metric and a robust loss: every option the CLI has on the way.
    rng = np.random.default_rng(5)
    n = 600
    ti, to = rng.uniform(0, 85, n), rng.uniform(0, 85, n)
    pi_, po = rng.uniform(-180, 180, n), rng.uniform(-180, 180, n)
    truth = aniso.ggx(kd=[0.2, 0.1, 0.05], f0=[0.6, 0.5, 0.4], alpha_x=0.1, alpha_y=0.25)
    f = truth.eval(aniso.direction(np.radians(ti), np.radians(pi_)), aniso.direction(np.radians(to), np.radians(po)))
    path = tmp / "samples.csv"
    with open(path, "w") as out:
        out.write("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n")
        for k in range(n):
            out.write(f"{ti[k]!r},{pi_[k]!r},{to[k]!r},{po[k]!r},{f[k, 0]!r},{f[k, 1]!r},{f[k, 2]!r}\n")
    fitted, _ = cli_fit(tmp, str(path), "--model", "ggx", "--anisotropic", "--metric", "log", "--loss", "cauchy",
                        "--starts", "3", "--seed", "11", "--max-iterations", "60")
    r = aniso.fit(path, model="ggx", anisotropic=True, metric="log", loss="cauchy", starts=3, seed=11,
                  max_iterations=60, progress=False)
    assert without_seconds(r.to_dict()) == without_seconds(fitted)
    assert r.fit["data"] == str(path) and r.fit["format"] == "csv"


def synthetic(truth, n, seed):
    """n pairs: uniform over the hemisphere, and a third of them within ~20 degrees of the mirror
    direction, with truth's values."""
    rng = np.random.default_rng(seed)
    theta_i, phi_i = np.arccos(rng.uniform(0.05, 1, n)), rng.uniform(-np.pi, np.pi, n)
    theta_o, phi_o = np.arccos(rng.uniform(0.05, 1, n)), rng.uniform(-np.pi, np.pi, n)
    k = n // 3
    theta_o[:k] = np.clip(theta_i[:k] + rng.normal(0, 0.15, k), 0, 1.5)
    phi_o[:k] = phi_i[:k] + np.pi + rng.normal(0, 0.2, k)
    wi, wo = aniso.direction(theta_i, phi_i), aniso.direction(theta_o, phi_o)
    return wi, wo, truth.eval(wi, wo)


def test_fit_recovers_parameters_from_arrays():
    truth = aniso.ggx(kd=[0.3, 0.2, 0.1], f0=[0.9, 0.6, 0.3], alpha_x=0.08, alpha_y=0.3)
    wi, wo, f = synthetic(truth, 2000, seed=2)
    # kd 0.3 + f0 0.9 reflect more than they receive near the horizon (GGX's kd is not coupled):
    # data that gain energy, fitted as they are.
    r = aniso.fit(wi=wi, wo=wo, value=f, model="ggx", anisotropic=True, allow_energy_gain=True, starts=3,
                  progress=False)
    got, want = r.material.to_dict(), truth.to_dict()
    for key in ["kd", "f0", "alpha_x", "alpha_y"]:
        np.testing.assert_allclose(got[key], want[key], rtol=1e-4, err_msg=key)
    assert r.errors["relative_l2cos"] < 1e-5
    # Ngan's 80 degrees (docs/fitting.md, "The range"): the samples beyond are left out and counted.
    assert r.samples + r.fit["range"]["samples_beyond"] == 2000 and r.fit["format"] == "arrays"
    # float32 arrays, a broadcast (3,) wi and weights are accepted; 2% noise: within a few percent.
    rng = np.random.default_rng(3)
    truth = aniso.ward(kd=0.2, ks=[0.3, 0.2, 0.1], alpha=0.15)
    wi, wo, f = synthetic(truth, 1500, seed=4)
    wo = wo[np.argsort(wo[:, 2])]
    wi1 = aniso.direction(np.radians(20), 0.0)
    f = truth.eval(wi1, wo) * (1 + 0.02 * rng.standard_normal((1500, 3)))
    r = aniso.fit(wi=wi1.astype(np.float32), wo=wo.astype(np.float32), value=f.astype(np.float32),
                  weight=np.ones(1500), model="ward", starts=2, progress=False)
    got = r.material.to_dict()
    np.testing.assert_allclose(got["ks"], [0.3, 0.2, 0.1], rtol=0.05)
    assert abs(got["alpha_x"] - 0.15) < 0.01 and got["alpha_x"] == got["alpha_y"]
    assert abs(np.mean(got["kd"]) - 0.2) < 0.02


def test_bad_data_and_options_raise_the_clis_messages(tmp):
    out = str(tmp / "never.json")
    for args, kwargs in [
        (["/nonexistent/x.brdf"], {}),
        ([KRYLON, "--lobes", "0"], {"lobes": 0}),
        ([KRYLON, "--lobes", "9"], {"lobes": 9}),
        ([KRYLON, "--model", "phongg"], {"model": "phongg"}),
        ([KRYLON, "--metric", "l3"], {"metric": "l3"}),
        ([KRYLON, "--loss", "tukey"], {"loss": "tukey"}),
        ([KRYLON, "--loss-scale", "-1"], {"loss_scale": -1}),
        ([KRYLON, "--starts", "0"], {"starts": 0}),
        ([KRYLON, "--seed", "-1"], {"seed": -1}),
        ([KRYLON, "--max-iterations", "0"], {"max_iterations": 0}),
        ([KRYLON, "--model", "ward", "--normalization", "walter"], {"model": "ward", "normalization": "walter"}),
        ([KRYLON, "--model", "metal", "--metal", "unobtainium"], {"model": "metal", "metal": "unobtainium"}),
        ([KRYLON, "--model", "metal", "--metal-lobe", "phong"], {"model": "metal", "metal_lobe": "phong"}),
    ]:
        expected = cli_error("fit", *args, "-q", "-o", out)
        data = args[0]
        with pytest.raises(ValueError) as e:
            aniso.fit(data, progress=False, **kwargs)
        assert str(e.value) == expected, args
    bad_csv = tmp / "bad.csv"
    bad_csv.write_text("theta_i,phi_i,theta_o,phi_o,r,g,b\n0.1,0,0.2,3,0.5,-0.1,0.5\n")
    expected = cli_error("fit", str(bad_csv), "-q", "-o", out)
    with pytest.raises(ValueError) as e:
        aniso.fit(bad_csv)
    assert str(e.value) == expected
    assert not os.path.exists(out)


def test_bad_arrays_raise_value_errors_naming_the_argument():
    wi, wo = aniso.direction([0.1, 0.2], [0, 1]), aniso.direction([0.3, 0.4], [2, 3])
    f = np.full((2, 3), 0.2)
    cases = [
        (dict(wi=wi, wo=wo), r"fit\(\): expected data .* or all of the arrays wi=, wo= and value="),
        (dict(wi=wi[:, :2], wo=wo, value=f), r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(2, 2\)"),
        (dict(wi=wi, wo=wo[:1], value=f), r"wi and wo: expected the same number of rows"),
        (dict(wi=wi * 2, wo=wo, value=f), r"wi: row 0: expected a unit direction above the horizon"),
        (dict(wi=wi, wo=wo * [1, 1, -1], value=f), r"wo: row 0: expected a unit direction above the horizon"),
        (dict(wi=wi, wo=wo, value=f * [1, -1, 1]), r"value: row 0: expected finite BRDF values >= 0"),
        (dict(wi=wi, wo=wo, value=np.where([[0], [1]], np.nan, f)), r"value: row 1: expected finite BRDF values"),
        (dict(wi=wi, wo=wo, value=f, weight=[1.0]), r"weight: expected an array of shape \(2,\)"),
        (dict(wi=wi, wo=wo, value=f, weight=[1.0, 0.0]), r"weight: row 1: expected a finite number > 0, got 0"),
        (dict(wi=wi, wo=wo, value=f.astype(complex)), r"value: expected .* got dtype complex128"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ValueError, match=message):
            aniso.fit(progress=False, **kwargs)
    with pytest.raises(ValueError, match="give either data"):
        aniso.fit(KRYLON, wi=wi, wo=wo, value=f)
    with pytest.raises(ValueError, match="lobes: expected a number, got list"):
        aniso.fit(KRYLON, lobes=[1])
    with pytest.raises(ValueError, match="progress: expected None, True, False or a callable, got int"):
        aniso.fit(KRYLON, progress=1)
    with pytest.raises(ValueError, match="no samples to fit"):
        aniso.fit(wi=np.zeros((0, 3)), wo=np.zeros((0, 3)), value=np.zeros((0, 3)))


def test_progress_callback_and_its_exceptions():
    seen = []
    r = aniso.fit(KRYLON, model="ggx", anisotropic="no", starts=2, progress=seen.append)
    assert seen and {"stage", "iteration", "cost", "elapsed_s", "remaining_s"} == set(seen[0])
    stages = [p["stage"] for p in seen]
    # starts=2 and, for a model with linear entries, the separable grid start beside them (docs/fitting.md).
    assert stages[0].startswith("start 1/3") and any(s.startswith("start 3/3") for s in stages)
    assert all(s.startswith(("start 1/3", "start 2/3", "start 3/3", "refining")) for s in stages)
    assert r.iterations > 0

    def fail(p):
        raise RuntimeError("stop here")
    with pytest.raises(RuntimeError, match="stop here"):
        aniso.fit(KRYLON, model="ggx", starts=2, progress=fail)


def test_the_gil_is_released_while_fitting():
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)
    t = threading.Thread(target=count)
    t.start()
    try:
        start = ticks
        aniso.fit(KRYLON, model="lafortune", lobes=2, starts=2, progress=False)
        during = ticks - start
    finally:
        done.set()
        t.join()
    assert during > 20, during  # the counting thread ran while the fit held the main thread


def test_ctrl_c_stops_a_fit_with_keyboard_interrupt():
    # Eight anisotropic Lafortune lobes from 200 starts: minutes; the flag is read every iteration.
    code = ("import aniso, sys\n"
            "print('ready', flush=True)\n"
            "try:\n"
            f"    aniso.fit({KRYLON!r}, lobes=8, anisotropic=True, starts=200, progress=False)\n"
            "    print('finished')\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted')\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.5)  # into the fit
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    assert out.strip() == "interrupted"
    assert time.monotonic() - start < 10


def test_messages_quoting_bytes_that_are_not_utf8_are_whole(tmp_path):
    # A file starting with \xff\xfe (a UTF-16 mark): the message quotes its first token, escaped
    # (io/text_escape.h), not an empty ValueError (issue 40, item 8).
    junk = tmp_path / "junk.brdf"
    junk.write_bytes(b"\xff\xfejunk\x1b[31m\n")
    with pytest.raises(ValueError) as e:
        aniso.fit(junk, model="ggx")
    message = str(e.value)
    assert "junk.brdf" in message and "\\xff\\xfe" in message and "\\u001b" in message, message
