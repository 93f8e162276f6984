"""fit-db's inputs and report (issue 40 items 5 and 7, issue 39 item 6): a folder's FIFO is skipped
with a note (a FIFO named on the command line fails its pairs) instead of blocking for ever; the
output folder inside an input folder is not read back (its results.csv is no measured file); the
report ranks by relative error; the figure holds every material name whole."""
import os
import sys

import pytest

from aniso import fit_db
from conftest import CLI, SOURCE_DIR, native_env  # noqa: F401
from test_fit_db import CLI_OPTIONS, OPTIONS, csv_rows, fit_many_quiet, run_fit_db

sys.path.insert(0, str(SOURCE_DIR / "python" / "bench"))
import fitdb_data  # noqa: E402


@pytest.fixture
def folder(tmp):
    """db/ with one small CSV file of an analytic material."""
    fitdb_data.make_database(tmp / "db", csv_count=1, seed=11, samples=200)
    return tmp / "db"


def test_the_output_folder_inside_an_input_folder_is_not_read_back(folder):
    # Before: the second run took db/fits/results.csv for a measured file (pair "results" failed, exit 1).
    for run in range(2):
        rc, out, err = run_fit_db(str(folder), "-o", str(folder / "fits"), "--models", "ward", "-q", *CLI_OPTIONS)
        assert rc == 0, (run, err)
        assert "1 of 1 pairs fitted" in out, (run, out)
    assert [r["material"] for r in csv_rows(folder / "fits" / "results.csv")] == ["csv00"]
    # The output folder as the input folder itself: its own files are skipped, the measured ones read.
    rows = fit_many_quiet([str(folder)], "ward", out=folder, workers=1, **OPTIONS)
    rows = fit_many_quiet([str(folder)], "ward", out=folder, workers=1, **OPTIONS)
    assert [(r["material"], r["status"]) for r in rows] == [("csv00", "ok")]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_is_skipped_in_a_folder_and_fails_its_pairs_when_named(folder, tmp):
    # Before: a FIFO named x.csv in the folder blocked fit-db for ever (the hash opened it).
    os.mkfifo(folder / "x.csv")
    rc, out, err = run_fit_db(str(folder), "-o", str(tmp / "out"), "--models", "ward", *CLI_OPTIONS, timeout=60)
    assert rc == 0, err
    assert f"aniso: note: {folder / 'x.csv'}: not a regular file" in err and "skipped" in err
    assert [r["material"] for r in csv_rows(tmp / "out" / "results.csv")] == ["csv00"]
    rc, out, err = run_fit_db(str(folder / "csv00.csv"), str(folder / "x.csv"), "-o", str(tmp / "out2"), "--models",
                              "ward", "-q", *CLI_OPTIONS, timeout=60)
    assert rc == 1, err
    rows = {r["material"]: r for r in csv_rows(tmp / "out2" / "results.csv")}
    assert rows["csv00"]["status"] == "ok"
    assert rows["x"]["status"] == "failed" and "not a regular file" in rows["x"]["error"], rows["x"]


def _row(material, model, l2cos, relative):
    return {"material": material, "model": model, "status": "ok", "l2cos": l2cos, "relative_l2cos": relative,
            "log": 0.1, "largest_albedo": 0.5}


def test_the_report_ranks_by_relative_error():
    # A bright material fitted to 1% and a dark one fitted to 50%: by absolute l2cos the dark one
    # looked better (0.01 < 1.0); by relative error it is the worse fit.
    rows = [_row("bright", "ward", 1.0, 0.01), _row("dark", "ward", 0.01, 0.5)]
    text = fit_db.report_markdown(rows, ["ward"], "l2cos", None)
    assert "relative l2cos" in text
    per_material = text[text.index("## Per material"):]
    assert per_material.index("| bright |") < per_material.index("| dark |")
    assert "| ward | 2 | 0.255 | 0.5 | dark |" in text  # median, worst and worst material by relative error
    # The log metric ranks by the log error the fits minimised.
    assert "median log" in fit_db.report_markdown(rows, ["ward"], "log", None)


def test_the_figure_holds_every_material_name_whole():
    long_names = ["a-material-with-a-rather-long-name-from-a-measured-database-" + "x" * i for i in range(0, 30, 5)]
    rows = [_row(m, "ward", 0.1, 0.01 * (i + 1)) for i, m in enumerate(long_names)] + [_row("$odd$", "ward", 0.1, 0.5)]
    fig = fit_db._figure(rows, ["ward"], "l2cos")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    figure_box = fig.bbox
    labels = ax.get_xticklabels() + [ax.yaxis.label, ax.title]
    assert [t.get_text() for t in ax.get_xticklabels()][-1] == r"\$odd\$"  # shown as typed, not as mathtext
    for t in labels:
        box = t.get_window_extent(renderer)
        assert box.x0 >= figure_box.x0 - 0.5 and box.y0 >= figure_box.y0 - 0.5, (t.get_text(), box, figure_box)
        assert box.x1 <= figure_box.x1 + 0.5 and box.y1 <= figure_box.y1 + 0.5, (t.get_text(), box, figure_box)
    import matplotlib.pyplot as plt
    plt.close(fig)
