"""Generated measured databases for aniso.fit_many's tests and benchmark (docs/fit-db.md): analytic
materials written as MERL .binary tables and CSV files of samples. Nothing is downloaded.

The MERL writer follows src/measured/merl.cpp (tabulate_merl, write_merl): f at each bin's centre
(theta_h = ((i + 1/2) / 90)^2 pi/2, theta_d = (j + 1/2) / 90 pi/2, phi_d = (k + 1/2) / 180 pi,
phi_h = 0), divided by MERL's scale factors; a bin with a direction below the horizon is missing
(-1). aniso.read_measured reads it back (its checks are the C++ reader's).
"""
import os

import numpy as np

import aniso

MERL_SCALE = (1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0)


def merl_bin_directions():
    """(wi, wo), each (90 * 90 * 180, 3), in merl_index order (phi_d fastest)."""
    i, j, k = np.meshgrid(np.arange(90), np.arange(90), np.arange(180), indexing="ij")
    u = (i.ravel() + 0.5) / 90
    theta_h = u * u * (np.pi / 2)
    theta_d = (j.ravel() + 0.5) / 90 * (np.pi / 2)
    phi_d = (k.ravel() + 0.5) / 180 * np.pi
    d = np.stack([np.sin(theta_d) * np.cos(phi_d), np.sin(theta_d) * np.sin(phi_d), np.cos(theta_d)], axis=1)
    ct, st = np.cos(theta_h)[:, None], np.sin(theta_h)[:, None]

    def rotate(v):
        return np.concatenate([v[:, :1] * ct + v[:, 2:] * st, v[:, 1:2], -v[:, :1] * st + v[:, 2:] * ct], axis=1)

    return rotate(d), rotate(d * np.array([-1.0, -1.0, 1.0]))


def write_merl(material, path):
    """The material as a MERL .binary file (35 MB)."""
    wi, wo = merl_bin_directions()
    above = (wi[:, 2] > 0) & (wo[:, 2] > 0)
    f = np.zeros((wi.shape[0], 3))
    f[above] = material.eval(wi[above], wo[above])
    stored = np.where(above[:, None], f / np.array(MERL_SCALE), -1.0)
    with open(path, "wb") as out:
        out.write(np.array([90, 90, 180], dtype="<i4").tobytes())
        out.write(np.ascontiguousarray(stored.T, dtype="<f8").tobytes())  # R block, G block, B block


def write_csv(material, path, n=400, seed=0):
    """n samples of the material (degrees, as `aniso fit` reads them): uniform over the hemisphere,
    a third of them near the mirror direction."""
    rng = np.random.default_rng(seed)
    ti = np.degrees(np.arccos(rng.uniform(0.1, 1, n)))
    pi_ = rng.uniform(-180, 180, n)
    to = np.degrees(np.arccos(rng.uniform(0.1, 1, n)))
    po = rng.uniform(-180, 180, n)
    k = n // 3
    to[:k] = np.clip(ti[:k] + rng.normal(0, 6, k), 0, 84)
    po[:k] = pi_[:k] + 180 + rng.normal(0, 6, k)
    po = (po + 180) % 360 - 180
    f = material.eval(aniso.direction(np.radians(ti), np.radians(pi_)), aniso.direction(np.radians(to), np.radians(po)))
    with open(path, "w") as out:
        out.write("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,r,g,b\n")
        for s in range(n):
            out.write(f"{ti[s]!r},{pi_[s]!r},{to[s]!r},{po[s]!r},{f[s, 0]!r},{f[s, 1]!r},{f[s, 2]!r}\n")


def random_material(rng):
    """An analytic material of one of four families with random parameters."""
    kind = rng.integers(4)
    kd = list(rng.uniform(0.02, 0.6, 3))
    if kind == 0:
        return aniso.ward(kd=kd, ks=list(rng.uniform(0.02, 0.5, 3)), alpha_x=float(rng.uniform(0.05, 0.4)),
                          alpha_y=float(rng.uniform(0.05, 0.4)))
    if kind == 1:
        return aniso.ggx(kd=kd, f0=list(rng.uniform(0.03, 0.9, 3)), alpha_x=float(rng.uniform(0.05, 0.5)),
                         alpha_y=float(rng.uniform(0.05, 0.5)))
    if kind == 2:
        n = float(10 ** rng.uniform(1, 3))
        return aniso.Material({"model": "ashikhmin-shirley", "rd": kd, "rs": list(rng.uniform(0.05, 0.6, 3)),
                               "n_u": n, "n_v": n})
    n = float(rng.uniform(5, 60))
    c = float(rng.uniform(0.7, 1.0))
    return aniso.Material({"model": "lafortune", "rho_d": kd,
                           "lobes": [{"cx": -c, "cy": -c, "cz": c, "n": n}]})


def make_database(folder, csv_count, merl_count=0, seed=0, samples=400):
    """csv_count CSV files and merl_count MERL files of random materials in folder; their paths."""
    os.makedirs(folder, exist_ok=True)
    rng = np.random.default_rng(seed)
    paths = []
    for i in range(csv_count + merl_count):
        m = random_material(rng)
        if i < merl_count:
            p = os.path.join(folder, f"merl{i:02d}.binary")
            write_merl(m, p)
        else:
            p = os.path.join(folder, f"csv{i - merl_count:02d}.csv")
            write_csv(m, p, n=samples, seed=int(rng.integers(1 << 30)))
        paths.append(p)
    return paths
