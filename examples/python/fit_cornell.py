#!/usr/bin/env python3
"""Fits a Cornell paint and plots measured against fitted slices in the plane of incidence.

Reads a Cornell gonioreflectometer file (data/measured/cornell/, spectra reduced to linear sRGB as
`aniso fit` reads them), fits one or more models with aniso.fit (the CLI's solver, options and
error figures), and draws, for four of the file's incidence angles, f (log scale) against the signed
outgoing angle in the plane of incidence (positive towards the mirror direction): the measured
samples within 1.5 degrees of the plane as dots, each fit as lines, one colour per channel. The
legend gives each fit's l2cos error over all samples and channels (docs/fitting.md, "Metrics").

    MPLBACKEND=Agg PYTHONPATH=build/release/python /usr/bin/python3 examples/python/fit_cornell.py \\
        data/measured/cornell/krylon_blue.brdf -o fit_cornell.png
"""
import argparse
import pathlib

import matplotlib.pyplot as plt
import numpy as np

import aniso

HERE = pathlib.Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parents[1] / "data" / "measured" / "cornell" / "krylon_blue.brdf"
CHANNELS = [("red", "#d62728"), ("green", "#2ca02c"), ("blue", "#1f77b4")]
LINESTYLES = ["-", "--", ":", "-."]
# Within 1.5 degrees of the plane of incidence: |wo . (plane normal)| = |wo.y| (phi_i = 0 in the
# Cornell files) below sin(1.5 degrees).
IN_PLANE = np.sin(np.radians(1.5))


def label_of(model, lobes):
    return f"{model} ({lobes} lobes)" if model == "lafortune" else model


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DATA), help="a Cornell .brdf file (or any file aniso fit reads)")
    ap.add_argument("-o", "--output", default="fit_cornell.png")
    ap.add_argument("--model", nargs="+", default=["ashikhmin-shirley", "lafortune"], help="models to fit (aniso.fit's model=)")
    ap.add_argument("--lobes", type=int, default=3, help="Lafortune lobes")
    ap.add_argument("--starts", type=int, default=6)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    data = aniso.read_measured(args.data)
    wi, wo, value = data["wi"], data["wo"], data["value"]
    fits = []
    for model in args.model:
        r = aniso.fit(args.data, model=model, lobes=args.lobes, starts=args.starts, seed=args.seed)
        fits.append((label_of(model, args.lobes), r))
        print(f"{label_of(model, args.lobes)}: l2cos {r.errors['l2cos']:.4g}, log {r.errors['log']:.4g}, "
              f"relative {r.errors['relative_l2cos']:.3f} ({r.iterations} iterations, best start {r.best_start})")

    # The incidence angles of the file (theta_i, rounded to 0.1 degree), four of them spread evenly.
    theta_i = np.round(np.degrees(np.arccos(np.clip(wi[:, 2], -1, 1))), 1)
    angles = np.unique(theta_i)
    shown = angles[np.linspace(0, len(angles) - 1, min(4, len(angles))).round().astype(int)]
    cols = 2 if len(shown) > 1 else 1
    rows_of_panels = (len(shown) + cols - 1) // cols
    fig, axes = plt.subplots(rows_of_panels, cols, figsize=(5.6 * cols, 4.3 * rows_of_panels), sharey=True, squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(shown):]:
        ax.set_visible(False)
    in_plane = np.abs(wo[:, 1]) < IN_PLANE
    # The signed outgoing angle: + on the mirror side (wo.x of the other sign than wi.x).
    signed = np.degrees(np.arccos(np.clip(wo[:, 2], -1, 1))) * np.where(wo[:, 0] * wi[:, 0] <= 0, 1, -1)
    lo, hi = np.inf, 0.0
    for ax, t in zip(axes, shown):
        rows = in_plane & (theta_i == t)
        light = aniso.direction(np.radians(t), 0.0)
        grid = np.linspace(-85, 85, 681)
        views = aniso.direction(np.radians(np.abs(grid)), np.where(grid >= 0, np.pi, 0.0))
        for k, (name, colour) in enumerate(CHANNELS):
            v = value[rows, k]
            ax.scatter(signed[rows], v, s=14, color=colour, edgecolor="black", linewidth=0.3, zorder=3,
                       label=f"measured ({name})" if k == 0 else None)
            pos = v[v > 0]
            if pos.size:
                lo, hi = min(lo, pos.min()), max(hi, pos.max())
            for j, (label, r) in enumerate(fits):
                f = r.material.eval(light, views)[:, k]
                ax.plot(grid, f, LINESTYLES[j % len(LINESTYLES)], color=colour, lw=1.2,
                        label=f"{label}, l2cos {r.errors['l2cos']:.3g}" if k == 0 else None)
        ax.axvline(t, color="0.6", lw=0.6, ls=":")
        ax.set_title(f"theta_i = {t:g} deg ({rows.sum()} samples in the plane)", fontsize=10)
        ax.set_xlabel("theta_o (deg) in the plane, + towards the mirror direction")
        ax.set_yscale("log")
        ax.set_xlim(-90, 90)
        ax.grid(True, which="major", color="0.9")
    for ax in axes[::cols]:
        ax.set_ylabel("f (1/sr): red, green, blue channel")
    axes[0].set_ylim(lo / 3, hi * 3)
    axes[0].legend(fontsize=8, loc="upper left")
    fig.suptitle(f"{pathlib.Path(args.data).name}: measured (dots) against fitted (lines)", fontsize=12)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
