#!/usr/bin/env python3
"""A plain least-squares fit of aniso's models, written outside the library: the yardstick that
`aniso fit` must match on real measurements (docs/fitting.md, "Real measurements").

The data are the samples `aniso fit` fits (aniso.read_measured: the same directions, values and
solid-angle weights); everything else is independent of the library: the models are transcribed
here from their documentation pages (docs/models/*.md, each equation cited below), and the fit is
SciPy's `least_squares` (trust-region reflective, bounds from the parameter tables) from
`--starts` random starts drawn from `--seed`, the best kept. No separable solve, no clever start:
what anyone would write in an afternoon.

Protocol (Ngan, Matusik & Durand 2005, Sec. 4, as docs/fitting.md states it): the residual of a
sample is sqrt(w) (f - m) cos(theta_i) per channel, over the samples with both directions within
`--max-theta` (default 80) degrees of the normal; the error is the relative l2cos,
sqrt(sum w (f - m)^2 cos^2 / sum w m^2 cos^2) over all three channels (0 exact, 1 as large as the
data). The solver sees a fixed random subset of at most `--solver-samples` samples; the error is
over every sample in range.

    /usr/bin/python3 bench/plain_fit.py FILE... [--models ggx,ward,...] [--json out.json]

Needs aniso's Python module on PYTHONPATH (build/release/python) and SciPy (python3-scipy).
"""
import argparse
import json
import math
import sys
import time

import numpy as np
from scipy.optimize import least_squares

import aniso

PI = math.pi


def half(wi, wo):
    h = wi + wo
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def schlick(f0, c):
    """Schlick 1994, Eq. 15: F(c) = f0 + (1 - f0)(1 - c)^5 (f0 per channel, c per sample)."""
    return f0[None, :] + (1.0 - f0[None, :]) * ((1.0 - np.clip(c, 0.0, 1.0)) ** 5)[:, None]


def ggx_lobe(wi, wo, ax, ay):
    """docs/models/ggx.md: D (Walter 2007 Eq. 33, anisotropic), height-correlated G2 (Heitz 2014
    Eq. 99), over 4 cos_i cos_o. Returns D G2 / (4 cos_i cos_o) and the half vector."""
    h = half(wi, wo)
    d = 1.0 / (PI * ax * ay * ((h[:, 0] / ax) ** 2 + (h[:, 1] / ay) ** 2 + h[:, 2] ** 2) ** 2)

    def lam(w):
        return (np.sqrt(1.0 + (ax * ax * w[:, 0] ** 2 + ay * ay * w[:, 1] ** 2) / w[:, 2] ** 2) - 1.0) / 2.0

    g2 = 1.0 / (1.0 + lam(wi) + lam(wo))
    return d * g2 / (4.0 * wi[:, 2] * wo[:, 2]), h


def conductor_fresnel(c, eta, k):
    """The unpolarised Fresnel reflectance of a conductor of index eta + i k (Born & Wolf; pbrt-v4's
    FrComplex): r_par = (n c - cos_t) / (n c + cos_t), r_perp = (c - n cos_t) / (c + n cos_t),
    F = (|r_par|^2 + |r_perp|^2) / 2, with n complex and cos_t = sqrt(1 - sin^2 / n^2)."""
    c = np.clip(c, 0.0, 1.0)[:, None]
    n = (eta + 1j * k)[None, :]
    sin2_t = (1.0 - c * c) / (n * n)
    cos_t = np.sqrt(1.0 - sin2_t)
    r_par = (n * c - cos_t) / (n * c + cos_t)
    r_perp = (c - n * cos_t) / (c + n * cos_t)
    return (np.abs(r_par) ** 2 + np.abs(r_perp) ** 2) / 2.0


def weights_and_alpha(rng):
    """A random start of a diffuse and a specular weight per channel and one alpha (GGX, Ward):
    weights uniform in [0, 1], alpha log-uniform in [0.02, 0.6]."""
    return np.r_[rng.uniform(0, 1, 3), rng.uniform(0, 1, 3), math.exp(rng.uniform(math.log(0.02), math.log(0.6)))]


class Model:
    """A model: parameter names, bounds, a random start, f(wi, wo, x) -> (N, 3), and aniso's JSON."""

    def __init__(self, name, names, lo, hi, start, f, to_json):
        self.name, self.names, self.lo, self.hi = name, names, np.array(lo, float), np.array(hi, float)
        self.start, self.f, self.to_json = start, f, to_json


def make_ggx():
    # docs/models/ggx.md: f = kd / pi + F(wi . h) D G2 / (4 cos_i cos_o); kd, f0 in [0, 1] per
    # channel, alpha in [0.001, 1] (the parameter table). Isotropic: alpha_x = alpha_y.
    def f(wi, wo, x):
        spec, h = ggx_lobe(wi, wo, x[6], x[6])
        return x[None, 0:3] / PI + schlick(x[3:6], np.sum(wi * h, axis=1)) * spec[:, None]

    return Model("ggx", ["kd.r", "kd.g", "kd.b", "f0.r", "f0.g", "f0.b", "alpha"], [0] * 6 + [1e-3], [1] * 7, weights_and_alpha, f,
                 lambda x: {"model": "ggx", "kd": list(x[0:3]), "f0": list(x[3:6]), "alpha": x[6]})


def make_ggx_f90():
    # docs/models/ggx.md with a free f90 per channel: F(c) = f0 (1 - w) + f90 w, w = (1 - c)^5
    # (Schlick's form with the grazing value free, as Filament writes it); f90 in [0, 1].
    def f(wi, wo, x):
        spec, h = ggx_lobe(wi, wo, x[9], x[9])
        w5 = ((1.0 - np.clip(np.sum(wi * h, axis=1), 0.0, 1.0)) ** 5)[:, None]
        return x[None, 0:3] / PI + (x[None, 3:6] * (1.0 - w5) + x[None, 6:9] * w5) * spec[:, None]

    def start(rng):
        x = weights_and_alpha(rng)
        return np.r_[x[0:6], rng.uniform(0, 1, 3), x[6]]

    return Model("ggx-f90", ["kd.r", "kd.g", "kd.b", "f0.r", "f0.g", "f0.b", "f90.r", "f90.g", "f90.b", "alpha"],
                 [0] * 9 + [1e-3], [1] * 10, start, f,
                 lambda x: {"model": "ggx", "kd": list(x[0:3]), "f0": list(x[3:6]), "f90": list(x[6:9]), "alpha": x[9]})


def make_ward():
    # docs/models/ward.md: f = kd / pi + ks N E, form "vector": E = exp(-((h.x/a)^2 + (h.y/a)^2) / h.z^2)
    # with h = wi + wo unnormalised; normalization "ward": N = 1 / (4 pi a^2 sqrt(cos_i cos_o)).
    def f(wi, wo, x):
        a = x[6]
        h = wi + wo
        e = np.exp(-((h[:, 0] / a) ** 2 + (h[:, 1] / a) ** 2) / h[:, 2] ** 2)
        n = 1.0 / (4.0 * PI * a * a * np.sqrt(wi[:, 2] * wo[:, 2]))
        return x[None, 0:3] / PI + x[None, 3:6] * (n * e)[:, None]

    return Model("ward", ["kd.r", "kd.g", "kd.b", "ks.r", "ks.g", "ks.b", "alpha"], [0] * 6 + [1e-3], [1] * 7, weights_and_alpha, f,
                 lambda x: {"model": "ward", "kd": list(x[0:3]), "ks": list(x[3:6]), "alpha": x[6]})


def make_as():
    # docs/models/ashikhmin-shirley.md, with rd = 0 as aniso's fit: f = ks_scale F(wi . h) f_s + kd / pi,
    # f_s = sqrt((n+1)(n+1)) / (8 pi) h.z^n / ((h . wi) max(cos_i, cos_o)), F Schlick with rs (grey).
    def f(wi, wo, x):
        n = x[7]
        h = half(wi, wo)
        hw = np.sum(h * wi, axis=1)
        fs = (n + 1.0) / (8.0 * PI) * h[:, 2] ** n / (hw * np.maximum(wi[:, 2], wo[:, 2]))
        fr = x[6] + (1.0 - x[6]) * (1.0 - np.clip(hw, 0, 1)) ** 5
        return x[None, 0:3] / PI + x[None, 3:6] * (fr * fs)[:, None]

    def start(rng):
        return np.r_[rng.uniform(0, 1, 3), rng.uniform(0.01, 1, 3), rng.uniform(0, 1), math.exp(rng.uniform(math.log(5),
                                                                                                              math.log(5000)))]

    return Model("ashikhmin-shirley", ["kd.r", "kd.g", "kd.b", "ks_scale.r", "ks_scale.g", "ks_scale.b", "rs", "n"],
                 [0] * 8, [1, 1, 1, 1e6, 1e6, 1e6, 1, 1e6], start, f,
                 lambda x: {"model": "ashikhmin-shirley", "rd": 0, "kd": list(x[0:3]), "ks_scale": list(x[3:6]), "rs": x[6],
                            "n": x[7]})


def make_lafortune(lobes):
    # docs/models/lafortune.md: f_c = rho_d,c / pi + sum_i max(C_xy,i,c (wi.x wo.x + wi.y wo.y) +
    # C_z,i,c wi.z wo.z, 0)^n_i,c per channel (isotropic: C_x = C_y), scale 1; C in [-100, 100],
    # n in [0, 1e6], rho_d in [0, 1]. Parameters: rho_d (3), then per lobe C_xy (3), C_z (3), n (3).
    def f(wi, wo, x):
        xy = wi[:, 0] * wo[:, 0] + wi[:, 1] * wo[:, 1]
        zz = wi[:, 2] * wo[:, 2]
        out = np.repeat(x[None, 0:3] / PI, len(wi), axis=0)
        for k in range(lobes):
            p = x[3 + 9 * k:12 + 9 * k]
            base = np.maximum(p[None, 0:3] * xy[:, None] + p[None, 3:6] * zz[:, None], 0.0)
            out = out + np.where(base > 0, base, 0.0) ** p[None, 6:9]
        return out

    def start(rng):
        x = list(rng.uniform(0, 1, 3))
        for k in range(lobes):
            n = math.exp(rng.uniform(math.log(1), math.log(500)))
            s = rng.uniform(0.5, 1.0) ** (1.0 / n)  # C such that the lobe's peak is about 1
            back = k > 0 and rng.uniform() < 0.2
            x += [s if back else -s] * 3 + [s] * 3 + [n] * 3
        return np.array(x)

    names = ["rho_d.r", "rho_d.g", "rho_d.b"]
    for k in range(lobes):
        names += [f"lobe{k}.{p}.{c}" for p in ("cxy", "cz", "n") for c in "rgb"]
    lo = [0] * 3 + ([-100] * 6 + [0] * 3) * lobes
    hi = [1] * 3 + ([100] * 6 + [1e6] * 3) * lobes

    def to_json(x):
        ls = [{"cxy": list(x[3 + 9 * k:6 + 9 * k]), "cz": list(x[6 + 9 * k:9 + 9 * k]), "n": list(x[9 + 9 * k:12 + 9 * k])}
              for k in range(lobes)]
        return {"model": "lafortune", "rho_d": list(x[0:3]), "lobes": ls}

    return Model(f"lafortune{lobes}", names, lo, hi, start, f, to_json)


def make_metal():
    # docs/models/metal.md: a GGX lobe (as ggx.md) with the exact conductor Fresnel of eta + i k per
    # channel, no diffuse; eta in [1e-3, 100] (aniso's fit bound), k in [0, 100].
    def f(wi, wo, x):
        spec, h = ggx_lobe(wi, wo, x[6], x[6])
        return conductor_fresnel(np.sum(wi * h, axis=1), x[0:3], x[3:6]) * spec[:, None]

    def start(rng):
        return np.r_[np.exp(rng.uniform(math.log(0.1), math.log(3), 3)), rng.uniform(1, 8, 3),
                     math.exp(rng.uniform(math.log(0.02), math.log(0.6)))]

    return Model("metal", ["eta.r", "eta.g", "eta.b", "k.r", "k.g", "k.b", "alpha"], [1e-3] * 3 + [0] * 3 + [1e-3],
                 [100] * 6 + [1], start, f,
                 lambda x: {"model": "metal", "eta": list(x[0:3]), "k": list(x[3:6]), "lobe": {"model": "ggx", "alpha": x[6]}})


MODELS = {"ggx": make_ggx, "ggx-f90": make_ggx_f90, "ward": make_ward, "ashikhmin-shirley": make_as, "lafortune1": lambda: make_lafortune(1),
          "lafortune3": lambda: make_lafortune(3), "metal": make_metal}


def relative_l2cos(model, x, wi, wo, m, w):
    f = model.f(wi, wo, x)
    c = wi[:, 2][:, None]
    num = np.sum(w[:, None] * ((f - m) * c) ** 2)
    den = np.sum(w[:, None] * (m * c) ** 2)
    return math.sqrt(num / den) if np.all(np.isfinite(f)) else float("inf")


def fit(model, wi, wo, m, w, starts, seed, solver_samples):
    rng = np.random.default_rng(seed)
    idx = np.arange(len(wi))
    if len(idx) > solver_samples:
        idx = np.sort(rng.choice(idx, solver_samples, replace=False))
    swi, swo, sm, sw = wi[idx], wo[idx], m[idx], w[idx]
    scale = math.sqrt(np.sum(sw[:, None] * (sm * swi[:, 2][:, None]) ** 2))
    sq = (np.sqrt(sw) * swi[:, 2])[:, None] / scale

    def residual(x):
        r = ((model.f(swi, swo, x) - sm) * sq).ravel()
        return np.nan_to_num(r, nan=1e3, posinf=1e3, neginf=-1e3)

    best = None
    for _ in range(starts):
        x0 = np.clip(model.start(rng), model.lo, model.hi)
        try:
            r = least_squares(residual, x0, bounds=(model.lo, model.hi), method="trf", x_scale="jac", max_nfev=400)
        except ValueError:
            continue
        if best is None or r.cost < best.cost:
            best = r
    return best.x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--models", default="ggx,ward,ashikhmin-shirley,lafortune1,lafortune3,metal")
    ap.add_argument("--starts", type=int, default=6)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-theta", type=float, default=80.0)
    ap.add_argument("--solver-samples", type=int, default=20000)
    ap.add_argument("--json", help="write every fit (parameters as aniso JSON, errors, seconds) here")
    a = ap.parse_args()
    results = []
    cmax = math.cos(math.radians(a.max_theta))
    for path in a.files:
        d = aniso.read_measured(path)
        keep = (d["wi"][:, 2] >= cmax) & (d["wo"][:, 2] >= cmax)
        wi, wo, m, w = d["wi"][keep], d["wo"][keep], d["value"][keep], d["weight"][keep]
        for name in a.models.split(","):
            model = MODELS[name]()
            t = time.process_time()
            x = fit(model, wi, wo, m, w, a.starts, a.seed, a.solver_samples)
            seconds = time.process_time() - t
            err = relative_l2cos(model, x, wi, wo, m, w)
            results.append({"file": path, "model": name, "relative_l2cos": err, "samples": int(len(wi)),
                            "material": model.to_json(x), "cpu_seconds": seconds})
            print(f"{path.split('/')[-1]:<32} {name:<18} relative l2cos {err:.4g}  ({seconds:.1f} s CPU)", flush=True)
    if a.json:
        with open(a.json, "w") as out:
            json.dump(results, out, indent=1, default=float)


if __name__ == "__main__":
    sys.exit(main())
