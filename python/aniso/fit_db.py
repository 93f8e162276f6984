"""Fitting whole databases: every model on every material (docs/fit-db.md).

``fit_many(inputs, models, client=None, ...)`` fits each (material file, model) pair with the
fitter of ``aniso fit`` (``aniso.fit``: the same solver, options and seed, so the same numbers), on
a local pool of threads (the fit releases the GIL) or, given a ``distributed.Client``, as one Dask
task per pair on the cluster's workers. With ``out=DIR`` it writes one fitted material JSON per
pair, ``results.csv`` and ``report.md`` (with ``report.png``, Ngan et al. 2005's comparison
figure), each file atomically, and a rerun skips the pairs already done with the same input bytes,
model and options. ``main()`` is the command line (``aniso fit-db``, ``python3 -m aniso.fit_db``).

Only the caller writes DIR: workers get a path (``shared_fs=True``) or the file's bytes, and
return the fitted material and its figures.
"""
from __future__ import annotations

import argparse
import csv
import hashlib
import io
import json
import math
import os
import signal
import socket
import sys
import tempfile
import threading
import time
import uuid
import warnings

import numpy as np

from . import _aniso

# The extensions aniso.fit reads (read_measured: include/aniso/measured/samples.h), which a folder is
# searched for (a file named on the command line is given to the reader whatever its extension).
MEASURED_EXTENSIONS = (".binary", ".brdf", ".bsdf", ".csv")

# A model spec is NAME or NAME:ARG; ARG is the option of aniso.fit that distinguishes the variants
# of NAME (as `aniso fit --compare` fits them: src/fit/fit.cpp, compare_models). Any other NAME
# is passed to aniso.fit as it is (without :ARG), which accepts every fittable model
# (aniso.fittable_models()) or names them. The choices of ward:ARG and metal:ARG are the parameter
# tables' (aniso.models()), as aniso.fit reads them.


def _choices(model, key):
    return next(p["choices"] for p in _aniso.models()[model]["params"] if p["name"] == key)


_NORMALIZATIONS = _choices("ward", "normalization")
_METAL_LOBES = _choices("metal", "lobe")
_SPEC_ARGUMENT = {
    "lafortune": ("lobes", "the number of lobes, 1 to 8"),
    "ward": ("normalization", " | ".join(_NORMALIZATIONS)),
    "metal": ("metal_lobe", " | ".join(_METAL_LOBES)),
}
DEFAULT_MODELS = "ward,ashikhmin-shirley,ggx,lafortune:1,lafortune:3"

# The fit options passed through to aniso.fit, with the values fit_many uses by default (those of
# `aniso fit`, except threads: one per task, the pool runs tasks side by side).
FIT_OPTIONS = {"anisotropic": "auto", "allow_energy_gain": False, "metric": "l2cos", "loss": "none", "loss_scale": 0.0,
               "starts": 6, "seed": 1, "max_iterations": 200, "threads": 1, "grid": None}
# The extension of the files that `grid` applies to: RGL tensor files, which have no samples of
# their own (aniso.fit(grid=), `aniso fit --grid`: check_rgl_fit_grid in measured/samples.h).
RGL_EXTENSION = ".bsdf"

CSV_COLUMNS = ["material", "model", "status", "l2cos", "l2cos_r", "l2cos_g", "l2cos_b", "log", "log_r", "log_g", "log_b",
               "relative_l2cos", "largest_albedo", "seconds", "best_start", "iterations", "samples", "parameters", "input",
               "input_sha256", "file", "aniso_version", "options", "error"]

STATE_DIR = ".fit-db"  # the per-pair records inside DIR (the resume state)


class FitDbError(ValueError):
    """A usage error: a missing input, an unknown model spec, a bad option (the CLI exits 2)."""


# --- model specs and inputs ----------------------------------------------------------------------

def parse_model_spec(spec):
    """'lafortune:3' -> ('lafortune:3', {'model': 'lafortune', 'lobes': 3}). The label is the spec
    as written (lafortune without a count is lafortune:1)."""
    text = spec.strip()
    name, _, arg = text.partition(":")
    if not name:
        raise FitDbError(f"--models: \"{spec}\": expected NAME or NAME:ARG")
    key, what = _SPEC_ARGUMENT.get(name, (None, None))
    kwargs = {"model": name}
    if arg:
        if key is None:
            raise FitDbError(f"--models: \"{spec}\": {name} takes no :ARG (lafortune:LOBES, ward:NORMALIZATION and "
                             "metal:LOBE do)")
        if key == "lobes":
            if not arg.isdigit():
                raise FitDbError(f"--models: \"{spec}\": expected {name}:N, N {what}")
            kwargs[key] = int(arg)
        else:
            kwargs[key] = arg
    elif name == "lafortune":
        kwargs["lobes"] = 1
        text = "lafortune:1"
    return text, kwargs


def parse_models(models):
    """A comma-separated text or a list of specs -> [(label, kwargs)], duplicates refused."""
    specs = models.split(",") if isinstance(models, str) else list(models)
    out, seen = [], set()
    for s in specs:
        if not str(s).strip():
            raise FitDbError(f"--models: an empty model in \"{models}\"")
        label, kwargs = parse_model_spec(str(s))
        if label in seen:
            raise FitDbError(f"--models: \"{label}\" is given twice")
        seen.add(label)
        out.append((label, kwargs))
    if not out:
        raise FitDbError("--models: no model given")
    return out


def _written_by_fit_db(out_real, root, dirs, files):
    """Prunes, in place, what fit-db writes from one step of a folder walk: the output folder
    (`out_real`, a real path) when the walk meets it below its start, and in any folder that is a
    fit-db output (it holds .fit-db/: this run's or an earlier one's, the walk's start included) its
    results.csv (which has a measured file's extension), materials/ and .fit-db/."""
    if out_real is not None:
        dirs[:] = [d for d in dirs if os.path.realpath(os.path.join(root, d)) != out_real]
    if STATE_DIR in dirs or (out_real is not None and os.path.realpath(root) == out_real):
        dirs[:] = [d for d in dirs if d not in ("materials", STATE_DIR)]
        files[:] = [f for f in files if f != "results.csv"]


def find_inputs(inputs, out=None, notes=None):
    """Files and folders -> [(name, path)]: a file as given, a folder's measured files (.binary,
    .brdf, .bsdf, .csv, searched recursively, in sorted order). The name is the file name without its
    extension; two inputs of one name are refused (their results would share files).

    A folder's entries that are not regular files (a FIFO, a device, a broken link) are skipped,
    each with a line in `notes` (a list, when given): reading them could block for ever. So are the
    files fit-db writes: the output folder `out` below an input folder, and the results.csv,
    materials/ and .fit-db/ of any fit-db output folder, so that a second run does not take its own
    results.csv for a measured file."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    out_real = os.path.realpath(os.fspath(out)) if out is not None else None
    paths = []
    for given in inputs:
        p = os.fspath(given)
        if os.path.isdir(p):
            found = []
            for root, dirs, files in os.walk(p):
                dirs.sort()
                _written_by_fit_db(out_real, root, dirs, files)
                for f in sorted(files):
                    if not f.endswith(MEASURED_EXTENSIONS):
                        continue
                    path = os.path.join(root, f)
                    if not os.path.isfile(path):  # follows links: a link to a regular file is read
                        if notes is not None:
                            notes.append(f"{path}: not a regular file (a FIFO, a device or a broken link): skipped")
                        continue
                    found.append(path)
            if not found:
                raise FitDbError(f"{p}: no measured files in this folder (expected {', '.join(MEASURED_EXTENSIONS)})")
            paths += found
        elif os.path.exists(p):
            paths.append(p)
        else:
            raise FitDbError(f"{p}: no such file or folder")
    named, by_name = [], {}
    for p in paths:
        name = os.path.splitext(os.path.basename(p))[0]
        if name in by_name:
            if os.path.realpath(by_name[name]) == os.path.realpath(p):
                continue
            raise FitDbError(f"two inputs are named \"{name}\": {by_name[name]} and {p} "
                             "(rename one: the results are named by file)")
        by_name[name] = p
        named.append((name, p))
    if not named:
        raise FitDbError("no input files given")
    return named


def _file_sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def check_grid(grid, what="grid"):
    """grid as aniso.fit's (the rules and messages of check_rgl_fit_grid, measured/samples.cpp):
    None, or an even integer from 4 to 256."""
    if grid is None:
        return None
    if isinstance(grid, bool) or not isinstance(grid, int):
        raise FitDbError(f"{what}: expected an integer or None, got {type(grid).__name__}")
    if grid < 4 or grid > 256:
        raise FitDbError(f"{what}: expected an even number from 4 to 256, got {grid}")
    if grid % 2 != 0:
        raise FitDbError(f"{what}: expected an even number (theta_d gets half of it), got {grid}")
    return grid


def _options_for(path, options):
    """The options of one input: grid (an RGL file's sampling grid) only for a .bsdf file; the
    other readers' samples are where they were measured, and their pairs' keys and rows do not
    name it."""
    if options.get("grid") is None or os.fspath(path).endswith(RGL_EXTENSION):
        return options
    return {k: v for k, v in options.items() if k != "grid"}


def _check_options(fit_options, model_kwargs):
    """Runs each model's options through aniso.fit's own checks (the CLI's messages) on a tiny data
    set before anything is scheduled: a bad option is one error, not one failure per pair. (grid,
    which aniso.fit refuses for arrays, is checked by check_grid.)"""
    import aniso
    fit_options = {k: v for k, v in fit_options.items() if k != "grid"}
    wi = aniso.direction(np.radians([10.0, 30.0, 50.0, 20.0]), np.radians([0.0, 40.0, 90.0, 200.0]))
    wo = aniso.direction(np.radians([20.0, 40.0, 10.0, 60.0]), np.radians([180.0, 220.0, 270.0, 10.0]))
    value = np.full((4, 3), 0.2)
    for label, kwargs in model_kwargs:
        opts = dict(fit_options, threads=1)
        try:
            aniso.fit(wi=wi, wo=wo, value=value, progress=False, **opts, **kwargs)
        except ValueError as e:
            raise FitDbError(f"{label}: {e}") from None


# --- one task: what a worker runs ------------------------------------------------------------------

def fit_pair(task, data=None, cancel=None):
    """Fits one (material, model) pair: aniso.fit on the file (task["path"]) or, when the worker
    does not share the caller's file system, on `data` (the file's bytes, written to a temporary
    file of the same name). Returns {"status": "ok", "fitted": fitted.json as a dict, ...} or, for
    input the reader or the options reject (ValueError, the CLI's message), {"status": "failed",
    "error": message}: a bad file fails its own pairs and is not retried. Any other exception
    propagates (Dask retries the task).  `cancel`: a threading.Event that stops the fit."""
    import aniso
    kwargs = dict(task["fit_options"], **task["model_kwargs"])
    progress = False
    if cancel is not None:
        def progress(_):
            if cancel.is_set():
                raise KeyboardInterrupt
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="aniso-fit-db-") as tmp:
        path = task["path"]
        if data is not None:
            path = os.path.join(tmp, os.path.basename(task["path"]))
            with open(path, "wb") as f:
                f.write(data)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                r = aniso.fit(path, progress=progress, **kwargs)
        except ValueError as e:
            message = str(e)
            if data is not None:  # the reader names the temporary file: name the caller's
                message = message.replace(path, task["path"])
            return {"status": "failed", "error": message, "seconds": time.perf_counter() - started}
    fitted = r.to_dict()
    fitted["fit"]["data"] = task["path"]
    # The fitter's own figure: the largest directional albedo over its grid (docs/fitting.md,
    # "Energy"), also in the fit object.
    return {"status": "ok", "fitted": fitted, "parameters": dict(r.parameters), "largest_albedo": r.largest_albedo,
            "warnings": [str(w.message) for w in caught], "seconds": time.perf_counter() - started,
            "worker": f"{socket.gethostname()}:{os.getpid()}"}


# --- the output folder -----------------------------------------------------------------------------

def write_atomically(path, data):
    """All or nothing: a temporary file beside `path`, flushed and renamed over it (as the C++
    writer, src/io/atomic_file.h), removed on any failure, Ctrl-C included."""
    if isinstance(data, str):
        data = data.encode()
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=f".{os.path.basename(path)}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


def _file_label(label):
    return label.replace(":", "-")


def _pair_id(material, label):
    return f"{material}.{_file_label(label)}"


def _pair_key(input_sha256, label, model_kwargs, fit_options, version):
    """What a result depends on: the input's bytes, the model and every option (threads aside:
    the fit is bit-identical for any thread count, docs/fitting.md), and the version."""
    options = {k: v for k, v in fit_options.items() if k != "threads"}
    text = json.dumps({"input": input_sha256, "model": label, "model_options": model_kwargs, "options": options,
                       "version": version}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def _row(material, label, path, sha, options, version, result):
    row = dict.fromkeys(CSV_COLUMNS, "")
    row.update(material=material, model=label, status=result["status"], input=path, input_sha256=sha,
               aniso_version=version, options=json.dumps(options, sort_keys=True), seconds=result.get("seconds", ""))
    if result["status"] == "ok":
        fit = result["fitted"]["fit"]
        e = fit["error"]
        row.update(l2cos=e["l2cos"], log=e["log"], relative_l2cos=e["relative_l2cos"], largest_albedo=result["largest_albedo"],
                   best_start=fit["best_start"], iterations=fit["iterations"], samples=fit["samples"],
                   parameters=json.dumps(result["parameters"]), seconds=fit["seconds"],
                   file=os.path.join("materials", _pair_id(material, label) + ".json"))
        for c, ch in enumerate("rgb"):
            row[f"l2cos_{ch}"] = e["l2cos_rgb"][c]
            row[f"log_{ch}"] = e["log_rgb"][c]
    else:
        row["error"] = result["error"]
    return row


class _Folder:
    """DIR: materials/<material>.<model>.json (the fitted material, as `aniso fit -o` writes it),
    .fit-db/<material>.<model>.json (the pair's record: its key and row; written after the
    material, so a record means a complete material file), results.csv, report.md, report.png."""

    def __init__(self, out):
        self.out = os.fspath(out)
        if os.path.exists(self.out) and not os.path.isdir(self.out):
            raise FitDbError(f"{self.out}: exists and is not a folder (-o names the output folder)")
        self.materials = os.path.join(self.out, "materials")
        self.state = os.path.join(self.out, STATE_DIR)
        for d in (self.out, self.materials, self.state):
            os.makedirs(d, exist_ok=True)

    def done(self, material, label, key):
        """The row recorded for this pair if it is finished with this key (and its material file
        is the one recorded), else None."""
        pid = _pair_id(material, label)
        try:
            with open(os.path.join(self.state, pid + ".json")) as f:
                record = json.load(f)
            with open(os.path.join(self.materials, pid + ".json"), "rb") as f:
                text = f.read()
        except (OSError, ValueError):
            return None
        if record.get("key") != key or record.get("material_sha256") != hashlib.sha256(text).hexdigest():
            return None
        return record["row"]

    def store(self, material, label, key, row, fitted):
        pid = _pair_id(material, label)
        text = json.dumps(fitted, indent=2) + "\n"
        write_atomically(os.path.join(self.materials, pid + ".json"), text)
        record = {"key": key, "material_sha256": hashlib.sha256(text.encode()).hexdigest(), "row": row}
        write_atomically(os.path.join(self.state, pid + ".json"), json.dumps(record, indent=1) + "\n")

    def summarise(self, rows, model_labels, metric):
        write_atomically(os.path.join(self.out, "results.csv"), results_csv(rows))
        png = os.path.join(self.out, "report.png")
        have_figure = write_figure(png, rows, model_labels, metric)
        write_atomically(os.path.join(self.out, "report.md"), report_markdown(rows, model_labels, metric,
                                                                               "report.png" if have_figure else None))


def results_csv(rows):
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=CSV_COLUMNS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in CSV_COLUMNS})
    return buf.getvalue()


def _metric_column(metric):
    """The column the report ranks by: for l2cos fits the relative l2cos error (l2cos over the
    data's own norm, docs/fitting.md "Metrics"), so that a bright material's fit does not look
    worse than a dark one's for its brightness alone; for log fits the log error they minimised.
    The absolute l2cos is in results.csv."""
    return "log" if metric == "log" else "relative_l2cos"


def _metric_name(metric):
    return "log" if metric == "log" else "relative l2cos"


def _error_table(rows, model_labels, metric):
    """{material: {label: error}} over the successful rows."""
    col = _metric_column(metric)
    table = {}
    for r in rows:
        if r["status"] == "ok" and r.get(col) not in (None, ""):
            table.setdefault(r["material"], {})[r["model"]] = float(r[col])
    return table


def _figure(rows, model_labels, metric):
    """The matplotlib figure of write_figure, or None without a successful row."""
    table = _error_table(rows, model_labels, metric)
    if not table:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    materials = sorted(table, key=lambda m: (min(table[m].values()), m))
    x = np.arange(len(materials))
    fontsize = 7 if len(materials) > 30 else 8
    # Room below the axes for the longest name, rotated: about 0.6 em per character (DejaVu Sans's
    # mean advance), 1 pt = 1/72 in.
    labels_in = max(len(m) for m in materials) * 0.6 * fontsize / 72.0
    fig, ax = plt.subplots(figsize=(max(6.0, min(24.0, 0.22 * len(materials) + 3.0)), 3.4 + labels_in), dpi=100)
    for label in model_labels:
        y = np.array([table[m].get(label, np.nan) for m in materials])
        y[~(y > 0)] = np.nan  # an exact fit (0) has no place on a log scale
        ax.plot(x, y, marker="o", markersize=3, linewidth=1.2, label=label)
    ax.set_yscale("log")
    ax.set_xticks(x)
    # "$" would start matplotlib's mathtext: the names are shown as they are.
    ax.set_xticklabels([m.replace("$", r"\$") for m in materials], rotation=90, fontsize=fontsize)
    ax.set_xlim(-0.5, len(materials) - 0.5)
    ax.set_ylabel(f"{_metric_name(metric)} error (all channels)")
    ax.set_title(f"{len(materials)} materials sorted by the best model's {_metric_name(metric)} error")
    ax.grid(True, which="major", axis="y", alpha=0.3)
    ax.legend(fontsize=8, ncol=min(len(model_labels), 4))
    fig.tight_layout()
    return fig


def write_figure(path, rows, model_labels, metric):
    """Ngan et al. 2005's figure: the materials on x, sorted by the best model's error, one line
    per model, the error on a log scale. False (nothing written) without a successful row."""
    fig = _figure(rows, model_labels, metric)
    if fig is None:
        return False
    import matplotlib.pyplot as plt
    buf = io.BytesIO()
    # bbox_inches="tight" also grows the image to hold every label whole, should a name's glyphs be
    # wider than _figure's estimate.
    fig.savefig(buf, format="png", metadata={"Software": None}, bbox_inches="tight", pad_inches=0.1)
    plt.close(fig)
    write_atomically(path, buf.getvalue())
    return True


def report_markdown(rows, model_labels, metric, figure):
    col = _metric_name(metric)
    table = _error_table(rows, model_labels, metric)
    materials = sorted({r["material"] for r in rows})
    failed = [r for r in rows if r["status"] != "ok"]
    lines = ["# Fits of a database", "",
             f"{len(materials)} materials x {len(model_labels)} models ({', '.join(model_labels)}): "
             f"{len(rows) - len(failed)} pairs fitted, {len(failed)} failed. Errors are the {col} error over every "
             f"sample and channel (docs/fitting.md, \"Metrics\")"
             + ("; relative: the l2cos error over the data's own l2cos norm, so that materials of any brightness "
                "compare" if metric != "log" else "") + "; every figure (absolute l2cos too) is in results.csv.", ""]
    if figure:
        lines += [f"![{col} error per material, sorted by the best model's]({figure})", ""]
    wins = dict.fromkeys(model_labels, 0)
    for m, errs in table.items():
        best = min(errs.values())
        for label, e in errs.items():
            if e == best:
                wins[label] += 1
    lines += [f"| model | fitted | median {col} | worst {col} | worst material | wins | albedo > 1 | failed |",
              "|---|---|---|---|---|---|---|---|"]
    for label in model_labels:
        errs = [(errs_m[label], m) for m, errs_m in table.items() if label in errs_m]
        nfail = sum(1 for r in failed if r["model"] == label)
        gain = sum(1 for r in rows if r["model"] == label and r["status"] == "ok" and float(r["largest_albedo"]) > 1)
        if errs:
            worst = max(errs)
            lines.append(f"| {label} | {len(errs)} | {float(np.median([e for e, _ in errs])):.4g} | {worst[0]:.4g} | "
                         f"{worst[1]} | {wins[label]} | {gain} | {nfail} |")
        else:
            lines.append(f"| {label} | 0 | | | | 0 | 0 | {nfail} |")
    lines += ["", "A win is a material on which the model's error is the smallest (ties count for each). "
              "Albedo > 1: fits whose largest directional albedo (results.csv; the fitter's grid, docs/fitting.md, "
              "\"Energy\") is above 1: they gain energy (allow_energy_gain, or the constraint could not hold it)."]
    if table:
        lines += ["", "## Per material", "", "| material | best | " + " | ".join(model_labels) + " |",
                  "|---|---|" + "---|" * len(model_labels)]
        for m in sorted(table, key=lambda m: (min(table[m].values()), m)):
            errs = table[m]
            best = min(errs, key=lambda label: (errs[label], model_labels.index(label)))
            cells = [f"{errs[label]:.4g}" if label in errs else "failed" for label in model_labels]
            lines.append(f"| {m} | {best} | " + " | ".join(cells) + " |")
    if failed:
        lines += ["", "## Failed pairs", "", "| material | model | reason |", "|---|---|---|"]
        for r in failed:
            reason = str(r["error"]).replace("|", "\\|").replace("\n", " ")
            lines.append(f"| {r['material']} | {r['model']} | {reason} |")
    return "\n".join(lines) + "\n"


# --- scheduling ------------------------------------------------------------------------------------

class _Progress:
    """done / total, failures, elapsed and time left over the whole job, on stderr: redrawn in
    place on a terminal, else one line every `every` seconds at most (and the last)."""

    def __init__(self, total, skipped, enabled, every=1.0):
        self.total, self.skipped, self.enabled = total, skipped, enabled
        self.done = self.failed = 0
        self.start = time.monotonic()
        self.tty = sys.stderr.isatty()
        self.every = 0.1 if self.tty else every
        self.last = -1e9
        self.shown = -1  # the done count of the last line

    def update(self, ok, final=False):
        if ok is not None:
            self.done += 1
            self.failed += 0 if ok else 1
        if not self.enabled:
            return
        now = time.monotonic()
        if (not final and now - self.last < self.every) or (final and self.shown == self.done):
            return
        self.last, self.shown = now, self.done
        elapsed = now - self.start
        todo = self.total - self.skipped
        left = elapsed / self.done * (todo - self.done) if self.done else float("nan")
        line = (f"fit-db: {self.skipped + self.done}/{self.total} pairs done ({self.skipped} already, {self.failed} failed), "
                f"{elapsed:.0f} s, " + (f"about {left:.0f} s left" if math.isfinite(left) else "time left unknown"))
        if self.tty:
            sys.stderr.write(f"\r{line:<100}" + ("\n" if final else ""))
        else:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()


def _default_workers():
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def _run_local(tasks, workers, on_result, interrupted):
    """A pool of `workers` threads (aniso.fit releases the GIL), at most 2 tasks per worker
    queued. Ctrl-C (`interrupted`, checked between results) stops the running fits at their next
    iteration; results are handed over whole, never half-stored."""
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
    pending = list(reversed(tasks))
    running = {}
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="fit-db") as pool:
        try:
            while pending or running:
                if interrupted.is_set():
                    raise KeyboardInterrupt
                while pending and len(running) < 2 * workers:
                    t = pending.pop()
                    running[pool.submit(fit_pair, t["task"], None, interrupted)] = t
                done, _ = wait(list(running), timeout=0.1, return_when=FIRST_COMPLETED)
                for fut in done:
                    t = running.pop(fut)
                    try:
                        result = fut.result()
                    except KeyboardInterrupt:  # the fit stopped by `interrupted`
                        raise
                    except Exception as e:  # an error of the library, not of the input
                        result = {"status": "failed", "error": f"{type(e).__name__}: {e}"}
                    on_result(t, result)
        except BaseException:
            interrupted.set()
            for fut in running:
                fut.cancel()
            raise


def _run_dask(tasks, client, shared_fs, retries, on_result, interrupted):
    """One Dask task per pair on the client's cluster, submitted a window at a time (at most
    2 per worker thread queued: a database of MERL files sent as bytes would otherwise sit in
    the scheduler's memory whole). A task whose worker dies is rescheduled by Dask (up to the
    scheduler's distributed.scheduler.allowed-failures, then KilledWorker); one that raises is
    retried `retries` times; both then count as failed pairs with the reason."""
    from distributed import as_completed
    threads = sum(client.nthreads().values()) or 1
    window = max(2, 2 * threads)
    pending = list(reversed(tasks))
    by_future = {}
    ac = as_completed()

    def submit():
        t = pending.pop()
        data = None
        if not shared_fs:
            with open(t["task"]["path"], "rb") as f:
                data = f.read()
        # A fresh key per submission: a key the scheduler still knows (an earlier run's, erred)
        # would hand back its old state.
        # The bytes go inside the task, not scattered ahead (Dask's "Large object ... in task graph"
        # advice): a scattered copy lives on one worker and dies with it, and the task retried
        # elsewhere would find its data gone. The window bounds what the scheduler holds.
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Large object of size")
            fut = client.submit(fit_pair, t["task"], data, key=f"fit-db-{t['id']}-{uuid.uuid4().hex[:12]}", pure=False,
                                retries=retries)
        by_future[fut] = t
        ac.add(fut)

    try:
        while pending and len(by_future) < window:
            submit()
        while by_future:
            if interrupted.is_set():
                raise KeyboardInterrupt
            if not ac.has_ready():  # polled, so that Ctrl-C is seen between results
                time.sleep(0.05)
                continue
            fut = next(ac)
            t = by_future.pop(fut)
            try:
                result = fut.result()
            except Exception as e:
                name = type(e).__name__
                if name == "KilledWorker":
                    reason = f"the workers running it died (KilledWorker, after the scheduler's allowed failures): {e}"
                else:
                    reason = f"{name} on the worker (after {retries} retries): {e}"
                result = {"status": "failed", "error": reason}
            fut.release()
            on_result(t, result)
            while pending and len(by_future) < window:
                submit()
    except BaseException:
        for fut in list(by_future):
            fut.cancel()
        raise


def _canonical_options(options):
    """One spelling per value, so that the same options give the same resume key and options
    column from Python and from the command line: loss_scale a float, the counts integers (1.0 is
    1); anything else is left for aniso.fit to accept or refuse with its message."""
    out = dict(options)
    if out.get("grid") is None:  # no key: the resume keys and options of runs without grid stay as they were
        out.pop("grid", None)
    if isinstance(out.get("anisotropic"), bool):  # aniso.fit's True / False are "yes" / "no"
        out["anisotropic"] = "yes" if out["anisotropic"] else "no"
    for k, v in out.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            continue
        if k == "loss_scale":
            out[k] = float(v)
        elif isinstance(v, float) and v.is_integer():
            out[k] = int(v)
    return out


def fit_many(inputs, models=DEFAULT_MODELS, client=None, *, out=None, workers=None, shared_fs=False, force=False,
             retries=2, progress=None, on_result=None, dataframe=True, grid=None, **fit_options):
    """Fits every model to every measured file: the rows of results.csv (docs/fit-db.md).

    inputs: files or folders (.binary, .brdf, .bsdf, .csv, folders searched recursively). models: specs
    such as "ward,ggx,lafortune:3" (a text or a list): NAME or NAME:ARG, NAME any of
    aniso.fittable_models(), ARG with lafortune:LOBES, ward:NORMALIZATION (aniso.fit's
    normalization) and metal:LOBE (its metal_lobe). fit_options: the keywords of aniso.fit (anisotropic, allow_energy_gain, metric,
    loss, loss_scale, starts, seed, max_iterations; threads: per task, default 1).

    client: a distributed.Client (each pair a Dask task on its workers, which must import aniso;
    shared_fs=True sends paths, otherwise the files' bytes); None: a pool of `workers` threads on
    this machine (default: every core). retries: Dask's retries of a task that raised.

    out: a folder to write (materials/, results.csv, report.md, report.png) and to resume from:
    pairs done with the same input bytes, model and options are not fitted again (force=True fits
    everything). progress: None (done/total and time left on stderr when it is a terminal, as
    aniso.fit), True (always), False, or a callable given each row as it finishes (on_result too).

    Returns a pandas DataFrame when pandas is installed (and dataframe=True), else a list of dicts,
    one per pair in input x model order; failed pairs have status "failed" and the reason in
    "error"."""
    import aniso
    unknown = set(fit_options) - set(FIT_OPTIONS)
    if unknown:
        raise FitDbError(f"unknown option(s) {', '.join(sorted(unknown))}: expected {', '.join(FIT_OPTIONS)}")
    check_grid(grid)  # before the canonical spelling, which would take 8.0 for 8 (aniso.fit refuses it)
    options = _canonical_options(dict(FIT_OPTIONS, **fit_options, grid=grid))
    model_list = parse_models(models)
    labels = [label for label, _ in model_list]
    _check_options(options, model_list)
    notes = []
    files = find_inputs(inputs, out=out, notes=notes)
    if progress is not False:
        for note in notes:
            sys.stderr.write(f"aniso: note: {note}\n")
    if options.get("grid") is not None and not any(os.fspath(p).endswith(RGL_EXTENSION) for _, p in files):
        raise FitDbError("grid applies to RGL tensor files (.bsdf) only, which have no samples of their own; "
                         "none of the inputs is one")
    version = aniso.__version__
    folder = _Folder(out) if out is not None else None

    rows, tasks = {}, []
    for name, path in files:
        if not os.path.isfile(path):  # named on the command line: its pairs fail (a FIFO's read could block)
            for label, _ in model_list:
                rows[(name, label)] = _row(name, label, path, "", _options_for(path, options), version,
                                           {"status": "failed",
                                            "error": f"{path}: not a regular file (a FIFO or a device): not read"})
            continue
        try:
            sha = _file_sha256(path)
        except OSError as e:
            sha = ""
            for label, _ in model_list:
                rows[(name, label)] = _row(name, label, path, sha, _options_for(path, options), version,
                                           {"status": "failed", "error": f"{path}: cannot read the file: {e.strerror}"})
            continue
        file_options = _options_for(path, options)
        for label, kwargs in model_list:
            key = _pair_key(sha, label, kwargs, file_options, version)
            if folder is not None and not force:
                row = folder.done(name, label, key)
                if row is not None:
                    rows[(name, label)] = row
                    continue
            tasks.append({"material": name, "label": label, "key": key, "sha": sha, "path": path,
                          "id": _pair_id(name, label).replace("/", "_"),
                          "task": {"path": os.path.abspath(path) if shared_fs or client is None else path,
                                   "model_kwargs": kwargs, "fit_options": file_options}})
    total = len(files) * len(model_list)
    display = _Progress(total, len(rows), progress is True or (progress is None and sys.stderr.isatty()))
    display.failed = sum(1 for r in rows.values() if r["status"] != "ok")
    lock = threading.Lock()

    def finished(t, result):
        # A pair is stored once: a second delivery of it (none is expected) is ignored.
        with lock:
            if (t["material"], t["label"]) in rows:
                return
            row = _row(t["material"], t["label"], t["path"], t["sha"], t["task"]["fit_options"], version, result)
            if result["status"] == "ok" and folder is not None:
                result["fitted"]["fit"]["data"] = t["path"]
                folder.store(t["material"], t["label"], t["key"], row, result["fitted"])
            rows[(t["material"], t["label"])] = row
            display.update(row["status"] == "ok")
            for cb in (on_result, progress if callable(progress) else None):
                if cb is not None:
                    cb(dict(row))

    # Ctrl-C sets `interrupted`; the runners raise KeyboardInterrupt between two results, so a
    # pair is stored whole (material file, then its record) or not at all. A second Ctrl-C raises
    # at once (each file is still written atomically).
    interrupted = threading.Event()
    previous = None
    if threading.current_thread() is threading.main_thread():
        def on_sigint(signum, frame):
            if interrupted.is_set():
                raise KeyboardInterrupt
            interrupted.set()
        previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        if tasks:
            if client is not None:
                _run_dask(tasks, client, shared_fs, retries, finished, interrupted)
            else:
                _run_local(tasks, workers or _default_workers(), finished, interrupted)
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        # Complete or interrupted, the summary files describe exactly the pairs done so far.
        ordered = [rows[(n, label)] for n, _ in files for label in labels if (n, label) in rows]
        if folder is not None:
            folder.summarise(ordered, labels, options["metric"])
        if display.enabled and display.done:
            display.update(None, final=True)
    if dataframe:
        try:
            import pandas
        except ImportError:
            return ordered
        return pandas.DataFrame(ordered, columns=CSV_COLUMNS)
    return ordered


# --- the command line ------------------------------------------------------------------------------

class _Parser(argparse.ArgumentParser):
    def error(self, message):
        """The CLI's form (docs/cli.md, "Exit status"): the usage, then "aniso: error: ...", exit 2."""
        self.print_usage(sys.stderr)
        self.exit(2, f"aniso: error: {message}\n")


def _parser(prog):
    p = _Parser(
        prog=prog, description="Fit every model to every material of a database (docs/fit-db.md): one fitted "
        "material JSON per pair, results.csv and report.md in DIR; a rerun resumes.")
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="measured files (.binary, .brdf, .bsdf, .csv) or folders of them")
    p.add_argument("--models", default=DEFAULT_MODELS,
                   help=f"comma-separated model specs: any model aniso fit fits ({', '.join(_aniso.fittable_models())}), "
                        f"ward[:{'|'.join(_NORMALIZATIONS)}], lafortune:LOBES, metal[:{'|'.join(_METAL_LOBES)}] "
                        "(default: %(default)s)")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="the output folder (created; resumed when it exists)")
    p.add_argument("--force", action="store_true", help="fit every pair again, even those DIR has")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, metavar="N",
                   help="start a Dask LocalCluster of N worker processes (one thread each); without it and --scheduler, "
                        "a pool of threads over the cores")
    g.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler (dask scheduler / dask worker)")
    p.add_argument("--threads", type=int, default=None, metavar="N",
                   help="local pool without Dask: N threads (default: every core)")
    p.add_argument("--shared-fs", action="store_true",
                   help="the workers see the inputs at the same paths: send paths, not the files' bytes")
    p.add_argument("--retries", type=int, default=2, help="Dask retries of a task that raised (default %(default)s)")
    fo = p.add_argument_group("fit options (as aniso fit)")
    fo.add_argument("--anisotropic", default="auto", metavar="auto|yes|no",
                    help="auto (default): anisotropic where the data show it; yes; no")
    fo.add_argument("--allow-energy-gain", action="store_true", help="let fits reach a directional albedo above 1")
    fo.add_argument("--metric", default="l2cos", help="l2cos | log (default %(default)s)")
    fo.add_argument("--loss", default="none", help="none | huber | cauchy | soft_l1")
    fo.add_argument("--loss-scale", default="0")
    fo.add_argument("--starts", default="6")
    fo.add_argument("--seed", default="1")
    fo.add_argument("--max-iterations", default="200")
    fo.add_argument("--grid", metavar="N",
                    help="the sampling grid of the .bsdf (RGL) inputs: N theta_h x N/2 theta_d x N phi_d, N even, 4 to 256 "
                         "(as aniso fit --grid; the other files are fitted at their own samples)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    return p


def _number(text):
    try:
        return int(text)
    except ValueError:
        return float(text)


def main(argv=None, prog="aniso fit-db"):
    """The command: exit 0 when every pair is fitted, 1 when some failed (report.md names them),
    2 for a usage error, 130 after Ctrl-C (DIR holds every pair finished before it)."""
    a = _parser(prog).parse_args(argv)
    options = {"anisotropic": a.anisotropic, "allow_energy_gain": a.allow_energy_gain, "metric": a.metric, "loss": a.loss,
               "starts": a.starts, "seed": a.seed,
               "max_iterations": a.max_iterations, "loss_scale": a.loss_scale}
    for k in ("starts", "seed", "max_iterations", "loss_scale"):
        try:
            options[k] = _number(options[k])
        except ValueError:
            print(f"aniso: error: --{k.replace('_', '-')}: expected a number, got \"{options[k]}\"", file=sys.stderr)
            return 2
    client = cluster = None
    try:
        if a.grid is not None:
            try:
                grid = int(a.grid)
            except ValueError:
                raise FitDbError(f"--grid: expected an even number from 4 to 256, got \"{a.grid}\"") from None
            options["grid"] = check_grid(grid, "--grid")
        if a.threads is not None and (a.workers is not None or a.scheduler):
            raise FitDbError("--threads sizes the local pool: with --workers or --scheduler Dask's workers run the tasks")
        if a.workers is not None and a.workers < 1:
            raise FitDbError(f"--workers: expected a number of worker processes >= 1, got {a.workers}")
        if a.retries < 0:
            raise FitDbError(f"--retries: expected a number >= 0, got {a.retries}")
        if a.workers is not None or a.scheduler:
            try:
                from distributed import Client, LocalCluster
            except ImportError:
                raise FitDbError("--workers and --scheduler need Dask's distributed package "
                                 "(Debian: apt-get install python3-distributed)") from None
            if a.scheduler:
                client = Client(a.scheduler, timeout="20s")
            else:
                cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=None)
                client = Client(cluster)
        rows = fit_many(a.inputs, a.models, client, out=a.out, workers=a.threads, shared_fs=a.shared_fs or cluster is not None,
                        force=a.force, retries=a.retries, progress=not a.quiet, dataframe=False, **options)
    except FitDbError as e:
        print(f"aniso: error: {e}", file=sys.stderr)
        return 2
    except ValueError as e:  # aniso's own checks (the CLI's messages)
        print(f"aniso: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"aniso: interrupted: {a.out} holds the pairs finished so far; the same command resumes", file=sys.stderr)
        return 130
    except OSError as e:
        print(f"aniso: error: {e}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    failed = [r for r in rows if r["status"] != "ok"]
    for r in failed:
        print(f"aniso: {r['material']} {r['model']}: failed: {r['error']}", file=sys.stderr)
    print(f"{len(rows) - len(failed)} of {len(rows)} pairs fitted; results in {os.path.join(a.out, 'results.csv')}, "
          f"report in {os.path.join(a.out, 'report.md')}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(prog="python3 -m aniso.fit_db"))
