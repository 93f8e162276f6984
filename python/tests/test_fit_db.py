"""aniso.fit_many and `aniso fit-db` (docs/fit-db.md) on generated databases (CSV files and a MERL
table of analytic materials, a Cornell paint): the same numbers as `aniso fit` on each pair alone,
a Dask LocalCluster with a worker SIGKILLed mid-job, resume after Ctrl-C, a corrupt file among good
ones, usage errors. Small fits (few starts and iterations) to keep the entry short."""
import csv
import json
import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

import aniso
from aniso import fit_db
from conftest import CLI, SOURCE_DIR, native_env, run_cli

sys.path.insert(0, str(SOURCE_DIR / "python" / "bench"))
import fitdb_data  # noqa: E402

KRYLON = str(SOURCE_DIR / "data/measured/cornell/krylon_blue.brdf")
# Isotropic fits only: "auto" fits every pair twice (isotropic and anisotropic) where the data
# cover the azimuths, as these CSV files do; the orchestration under test is the same.
OPTIONS = {"starts": 2, "seed": 3, "max_iterations": 30, "anisotropic": "no"}
CLI_OPTIONS = ["--starts", "2", "--seed", "3", "--max-iterations", "30", "--anisotropic", "no"]
MODELS = "ward,lafortune:2"
SANITIZER = bool(os.environ.get("ANISO_SANITIZER_PRELOAD"))
# In the sanitizer build every Dask worker process would be another interpreter starting with the
# ASan runtime preloaded (slow, and not what the sanitizers are there to check); the thread pool's
# tests run there, the task function (fit_pair) and the CLI's launcher included.
NO_DASK_UNDER_ASAN = "sanitizer build: Dask worker processes are not started under the ASan preload"


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    """Three CSV files of random analytic materials and a Cornell paint."""
    d = tmp_path_factory.mktemp("db")
    paths = fitdb_data.make_database(d / "csv", csv_count=3, seed=7, samples=300)
    return d, paths + [KRYLON]


def without_seconds(fitted):
    d = json.loads(json.dumps(fitted))
    d["fit"].pop("seconds")
    return d


def csv_rows(path, drop=("seconds",)):
    with open(path) as f:
        return [{k: v for k, v in r.items() if k not in drop} for r in csv.DictReader(f)]


def test_results_equal_aniso_fit_on_each_pair(db, tmp):
    d, paths = db
    rows = fit_many_quiet([str(p) for p in paths], MODELS, out=tmp / "out", workers=2, **OPTIONS)
    assert [r["status"] for r in rows] == ["ok"] * 2 * len(paths), [r["error"] for r in rows]
    merl_rows = []
    if not SANITIZER:  # (under ASan the MERL fits' 1.5 M samples would take minutes; test_merl.cpp reads MERL there)
        # A MERL table too (Ward alone, to keep the entry short): the 35 MB format, weights and subset.
        merl = tmp / "ward.binary"
        fitdb_data.write_merl(aniso.ward(kd=[0.1, 0.2, 0.3], ks=[0.3, 0.2, 0.1], alpha_x=0.15, alpha_y=0.15), merl)
        merl_rows = fit_many_quiet([str(merl)], "ward", out=tmp / "out-merl", workers=1, **OPTIONS)
    for r, out in [(r, tmp / "out") for r in rows] + [(r, tmp / "out-merl") for r in merl_rows]:
        spec = {"ward": ["--model", "ward"], "lafortune:2": ["--model", "lafortune", "--lobes", "2"]}[r["model"]]
        rc, _, err = run_cli("fit", r["input"], *spec, *CLI_OPTIONS, "-q", "-o", str(tmp / "one.json"))
        assert rc == 0, err
        alone = json.loads((tmp / "one.json").read_text())
        ours = json.loads((out / r["file"]).read_text())
        assert without_seconds(ours) == without_seconds(alone), (r["material"], r["model"])
        assert float(r["l2cos"]) == alone["fit"]["error"]["l2cos"]
        assert float(r["largest_albedo"]) == alone["fit"]["largest_albedo"]["value"]
        assert json.loads(r["parameters"]) and all(isinstance(v, float) for v in json.loads(r["parameters"]).values())
        assert aniso.Material(str(out / r["file"])) == aniso.Material(str(tmp / "one.json"))
    report = (tmp / "out" / "report.md").read_text()
    assert "![" in report and (tmp / "out" / "report.png").stat().st_size > 1000
    assert "| ward |" in report and "| lafortune:2 |" in report
    assert csv_rows(tmp / "out" / "results.csv") == [{k: str(v) for k, v in r.items() if k != "seconds"} for r in rows]


def fit_many_quiet(inputs, models, **kw):
    return aniso.fit_many(inputs, models, progress=False, dataframe=False, **kw)


@pytest.mark.skipif(SANITIZER, reason=NO_DASK_UNDER_ASAN)
def test_dask_local_cluster_survives_a_killed_worker(db, tmp):
    distributed = pytest.importorskip("distributed")
    _, paths = db
    inputs = [str(p) for p in paths]
    # A corrupt file too: sent as bytes, its pairs fail with the reader's message naming the
    # caller's path, not the worker's temporary copy.
    bad = tmp / "bad.csv"
    bad.write_text("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n10,0,20,180,0.1,-0.2,0.3\n")
    local = fit_many_quiet(inputs + [str(bad)], MODELS, workers=2, **OPTIONS)
    assert [r["status"] for r in local] == ["ok"] * 2 * len(inputs) + ["failed"] * 2
    assert local[-1]["error"].startswith(f"{bad}: line 2")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        # Only the caller writes: the workers get the files' bytes (no shared file system assumed).
        same = fit_many_quiet(inputs + [str(bad)], MODELS, client=client, out=tmp / "dask", **OPTIONS)
        assert [{k: v for k, v in r.items() if k != "seconds"} for r in same] == \
               [{k: v for k, v in r.items() if k != "seconds"} for r in local]

        pids = client.run(os.getpid)
        killed = []

        def kill_a_busy_worker(row):
            if killed:
                return
            busy = [addr for addr, keys in client.processing().items() if keys and addr in pids]
            if busy:
                os.kill(pids[busy[0]], signal.SIGKILL)
                killed.append(busy[0])

        seen = []
        rows = fit_many_quiet(inputs, MODELS, client=client, out=tmp / "dask", force=True,
                              on_result=lambda r: (seen.append((r["material"], r["model"])), kill_a_busy_worker(r)),
                              **OPTIONS)
        assert killed, "no worker was running a task when the first result came back"
        assert [r["status"] for r in rows] == ["ok"] * len(rows), [r["error"] for r in rows]
        assert sorted(seen) == sorted((r["material"], r["model"]) for r in rows)  # every pair once
        assert len(seen) == 2 * len(inputs)
        assert [r["l2cos"] for r in rows] == [r["l2cos"] for r in local[:len(rows)]]


@pytest.mark.skipif(SANITIZER, reason=NO_DASK_UNDER_ASAN)
def test_cli_workers_starts_a_local_cluster(db, tmp):
    pytest.importorskip("distributed")
    _, paths = db
    rc, out, err = run_fit_db(str(paths[0]), str(paths[1]), "--models", "ward", "-o", str(tmp / "o"), "--workers", "2",
                              *CLI_OPTIONS)
    assert rc == 0, err
    assert "2 of 2 pairs fitted" in out
    alone = fit_many_quiet([str(paths[0]), str(paths[1])], "ward", workers=1, **OPTIONS)
    assert csv_rows(tmp / "o" / "results.csv", drop=("seconds", "input")) == [
        {k: str(v) for k, v in r.items() if k not in ("seconds", "input")} for r in alone]


def run_fit_db(*args, timeout=120):
    p = subprocess.run([CLI, "fit-db", *args], capture_output=True, text=True, timeout=timeout, env=native_env())
    return p.returncode, p.stdout, p.stderr


def test_ctrl_c_then_rerun_resumes_and_matches_an_uninterrupted_run(db, tmp):
    _, paths = db
    inputs = [str(p) for p in paths]
    options = ["--starts", "4", "--seed", "3", "--max-iterations", "60", "--anisotropic", "no"]
    whole = tmp / "whole"
    rc, out, err = run_fit_db(*inputs, "--models", MODELS, "-o", str(whole), "--threads", "2", *options)
    assert rc == 0, err
    assert "8 of 8 pairs fitted" in out and "fit-db: 8/8 pairs done" in err

    part = tmp / "part"
    p = subprocess.Popen([CLI, "fit-db", *inputs, "--models", MODELS, "-o", str(part), "--threads", "1", *options],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=native_env())
    state = part / fit_db.STATE_DIR
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and p.poll() is None and len(list(state.glob("*.json"))) < 2:
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert "resumes" in err
    done = {f.name: f.read_bytes() for f in state.glob("*.json")}
    assert 2 <= len(done) < 8
    # Everything written is complete: no temporaries, every material file reads.
    assert not [f for f in part.rglob("*") if f.name.endswith(".tmp")]
    for f in (part / "materials").glob("*.json"):
        aniso.Material(str(f))
    assert len(csv_rows(part / "results.csv")) == len(list((part / "materials").glob("*.json")))

    rc, out, err = run_fit_db(*inputs, "--models", MODELS, "-o", str(part), "--threads", "2", *options)
    assert rc == 0, err
    assert f"({len(done)} already, 0 failed)" in err
    for name, content in done.items():  # nothing redone
        assert (state / name).read_bytes() == content
    for f in (whole / "materials").glob("*.json"):
        assert without_seconds(json.loads(f.read_text())) == without_seconds(json.loads((part / "materials" / f.name).read_text()))
    assert csv_rows(whole / "results.csv") == csv_rows(part / "results.csv")
    assert (whole / "report.md").read_bytes() == (part / "report.md").read_bytes()
    assert (whole / "report.png").read_bytes() == (part / "report.png").read_bytes()

    # Another option is another job: everything is fitted again; so does --force.
    rc, _, err = run_fit_db(*inputs, "--models", "ward", "-o", str(part), *options, "--seed", "4")
    assert rc == 0 and "(0 already" in err, err
    rc, _, err = run_fit_db(*inputs, "--models", "ward", "-o", str(part), *options, "--seed", "4", "--force")
    assert rc == 0 and "(0 already" in err, err


def test_a_corrupt_file_fails_only_its_pairs(db, tmp):
    _, paths = db
    bad = tmp / "bad.csv"
    bad.write_text("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n10,0,20,180,0.1,0.2,0.3\n10,0,20,180,0.1,nan,0.3\n")
    short = tmp / "short.binary"
    short.write_bytes(b"\x5a\x00\x00\x00\x5a\x00\x00\x00\xb4\x00\x00\x00" + b"\x00" * 64)
    inputs = [str(paths[0]), str(bad), str(short), str(paths[1])]
    rc, out, err = run_fit_db(*inputs, "--models", "ward,ggx", "-o", str(tmp / "out"), *CLI_OPTIONS)
    assert rc == 1, err
    assert "4 of 8 pairs fitted" in out
    rows = csv_rows(tmp / "out" / "results.csv")
    status = {(r["material"], r["model"]): (r["status"], r["error"]) for r in rows}
    assert len(status) == 8
    for name in ("bad", "short"):
        for model in ("ward", "ggx"):
            s, message = status[(name, model)]
            assert s == "failed"
            assert message.startswith(str(tmp / name)), message  # the reader's message, naming the file
    assert "line 3" in status[("bad", "ward")][1] and "nan" in status[("bad", "ward")][1]
    assert [s for (m, _), (s, _) in status.items() if m not in ("bad", "short")] == ["ok"] * 4
    report = (tmp / "out" / "report.md").read_text()
    assert "## Failed pairs" in report and "| bad | ward |" in report
    assert f"aniso: bad ward: failed: {bad}" in err
    assert sorted(f.name for f in (tmp / "out" / "materials").iterdir()) == sorted(
        f"{pathlib.Path(p).stem}.{m}.json" for p in (paths[0], paths[1]) for m in ("ward", "ggx"))


def test_usage_errors(db, tmp):
    _, paths = db
    cases = [
        (["--models", "blinn"], "blinn: --model: expected "),
        (["--models", "ggx:2"], "ggx takes no :ARG"),
        (["--models", "lafortune:x"], "expected lafortune:N"),
        (["--models", "lafortune:9"], "lafortune:9: --lobes"),
        (["--models", "ward,ward"], "\"ward\" is given twice"),
        (["--models", "ward", "--metric", "cos"], "--metric"),
        (["--models", "ward", "--starts", "0"], "--starts"),
        (["--models", "ward", "--workers", "0"], "--workers"),
    ]
    for args, expected in cases:
        rc, out, err = run_fit_db(str(paths[0]), "-o", str(tmp / "o"), *args)
        assert rc == 2 and out == "", (args, err)
        assert err.startswith("aniso: error: ") and expected in err, (args, err)
    rc, _, err = run_fit_db(str(tmp / "nothing"), "-o", str(tmp / "o"))
    assert rc == 2 and f"{tmp / 'nothing'}: no such file or folder" in err
    (tmp / "file").write_text("")
    rc, _, err = run_fit_db(str(paths[0]), "-o", str(tmp / "file"), "--models", "ward")
    assert rc == 2 and "file: exists and is not a folder" in err
    (tmp / "empty").mkdir()
    rc, _, err = run_fit_db(str(tmp / "empty"), "-o", str(tmp / "o"))
    assert rc == 2 and "no measured files in this folder" in err
    env = dict(native_env(), ANISO_PYTHON=str(tmp / "no-python3"))
    p = subprocess.run([CLI, "fit-db", str(paths[0]), "-o", str(tmp / "o")], capture_output=True, text=True, env=env)
    assert p.returncode == 2 and f"fit-db runs in Python: cannot run the interpreter {tmp / 'no-python3'}" in p.stderr
    rc, out, _ = run_fit_db("--help")
    assert rc == 0 and "usage: aniso fit-db" in out and "--scheduler" in out
    # The Python call: the same checks, as ValueError.
    with pytest.raises(ValueError, match="blinn: --model: expected"):
        aniso.fit_many(paths[:1], "blinn")
    with pytest.raises(ValueError, match="unknown option"):
        aniso.fit_many(paths[:1], "ward", stars=3)


def test_model_specs_and_rows_without_pandas(db):
    assert fit_db.parse_models("ward:duer, ggx,lafortune,metal:ward") == [
        ("ward:duer", {"model": "ward", "normalization": "duer"}), ("ggx", {"model": "ggx"}),
        ("lafortune:1", {"model": "lafortune", "lobes": 1}), ("metal:ward", {"model": "metal", "metal_lobe": "ward"})]
    _, paths = db
    rows = aniso.fit_many(paths[0], ["ward"], progress=False, workers=1, **OPTIONS)
    try:
        import pandas  # noqa: F401
        assert list(rows["model"]) == ["ward"]
    except ImportError:
        assert isinstance(rows, list) and rows[0]["model"] == "ward" and rows[0]["status"] == "ok"


def test_grid_sets_the_sampling_of_the_rgl_inputs_only(db, tmp):
    # grid=N / --grid N as aniso.fit's: the .bsdf inputs are sampled on that grid (the same numbers
    # as aniso.fit(path, grid=N)); the other files are fitted at their own samples, and their
    # keys and options do not name it. Refused with aniso.fit's messages when out of range or odd,
    # and when no input is a .bsdf file.
    _, paths = db
    bsdf = tmp / "ggx.bsdf"
    rc, _, stderr = run_cli("export-rgl", "--material", '{"model": "ggx", "kd": 0.1, "f0": 0.5, "alpha": 0.2}', "--rgb",
                            "--resolution", "8", "--theta-i", "4", "--ndf", "16", "-o", str(bsdf))
    assert rc == 0, stderr
    rows = fit_many_quiet([str(bsdf), str(paths[0])], "ggx", out=tmp / "out", workers=2, grid=8, **OPTIONS)
    assert [r["status"] for r in rows] == ["ok", "ok"], [r["error"] for r in rows]
    assert json.loads(rows[0]["options"])["grid"] == 8 and "grid" not in json.loads(rows[1]["options"])
    r = aniso.fit(bsdf, model="ggx", progress=False, grid=8, **OPTIONS)
    with open(tmp / "out" / rows[0]["file"]) as f:
        fitted = json.load(f)
    assert "8 theta_h (square-root spaced)" in fitted["fit"]["sampled"]
    fitted["fit"].pop("data")
    expected = r.to_dict()
    expected["fit"].pop("data", None)
    assert without_seconds(fitted) == without_seconds(expected)
    other = fit_many_quiet([str(paths[0])], "ggx", **OPTIONS)
    assert other[0]["parameters"] == rows[1]["parameters"]
    # The command line: the same keys as the Python call (both pairs resumed, nothing fitted again),
    # and the same rows after a fit from scratch.
    before = csv_rows(tmp / "out" / "results.csv", drop=())
    rc, out, err = run_fit_db(str(bsdf), str(paths[0]), "-o", str(tmp / "out"), "--models", "ggx", "--grid", "8", "-q",
                              *CLI_OPTIONS)
    assert rc == 0, err
    assert csv_rows(tmp / "out" / "results.csv", drop=()) == before  # the seconds too: nothing was fitted again
    rc, out, err = run_fit_db(str(bsdf), str(paths[0]), "-o", str(tmp / "cli"), "--models", "ggx", "--grid", "8", "-q",
                              *CLI_OPTIONS)
    assert rc == 0, err
    drop = ("seconds", "file", "input")
    assert csv_rows(tmp / "cli" / "results.csv", drop) == csv_rows(tmp / "out" / "results.csv", drop)
    for args, expected in [(["--grid", "7"], "--grid: expected an even number (theta_d gets half of it), got 7"),
                           (["--grid", "2"], "--grid: expected an even number from 4 to 256, got 2"),
                           (["--grid", "x"], "--grid: expected an even number from 4 to 256, got \"x\"")]:
        rc, out, err = run_fit_db(str(bsdf), "-o", str(tmp / "o"), "--models", "ggx", *args)
        assert rc == 2 and out == "" and err.startswith("aniso: error: ") and expected in err, (args, err)
    rc, _, err = run_fit_db(str(paths[0]), "-o", str(tmp / "o"), "--models", "ggx", "--grid", "8")
    assert rc == 2 and "grid applies to RGL tensor files (.bsdf) only" in err, err
    with pytest.raises(ValueError, match="grid: expected an even number from 4 to 256, got 258"):
        aniso.fit_many([str(bsdf)], "ggx", grid=258)
    with pytest.raises(ValueError, match="grid: expected an integer or None, got float"):
        aniso.fit_many([str(bsdf)], "ggx", grid=8.0)
