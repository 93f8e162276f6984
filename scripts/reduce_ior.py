#!/usr/bin/python3
"""Reduce measured spectral complex refractive indices of metals to RGB.

This script is the project's single place where spectral optical constants
n(lambda) + i k(lambda) are turned into per-channel RGB values.  The method is
documented in docs/metals.md; the steps are:

 1. Parse the tabulated n, k data copied into data/ior/ (refractiveindex.info
    YAML "tabulated nk" blocks, wavelength in micrometres; pbrt-v4 CSV named
    spectra, wavelength in nm, eta and k in separate files).
 2. Resample n and k linearly onto 380..780 nm every 5 nm (81 samples),
    clamping to the end values where the data does not cover the range.
 3. Evaluate the exact unpolarised Fresnel reflectance of an air/conductor
    interface R(lambda, theta) (Born & Wolf, "Principles of Optics", sec. 14.2;
    same formula as pbrt-v4 FrComplex) on a grid of incidence angles.
 4. Reduce R(lambda, theta) to linear sRGB: integrate against the CIE 1931 2-deg
    colour matching functions (analytic multi-lobe fit, Wyman, Sloan & Shirley
    2013, JCGT 2(2), eq. 2) under an equal-energy illuminant E, convert XYZ to
    linear sRGB (IEC 61966-2-1 primaries), and divide each channel by the value
    of a perfect reflector (R = 1), so that a non-selective reflector maps to
    the same value in all channels (von Kries-style white balance in RGB).
 5. Per metal and channel, fit (eta_c, k_c) such that the exact conductor
    Fresnel curve F(theta; eta_c, k_c) best matches the reduced R_c(theta) in
    least squares over the angle grid.
 6. Write src/data/metal_table.inc (generated; do not edit by hand), and the
    resampled n, k of step 2 to src/data/metal_spectra.inc (what spectral
    exports evaluate the Fresnel equation with: docs/rgl.md, "Spectral files").

Usage (run with Debian's Python, which has numpy and scipy:
       apt-get install python3-numpy python3-scipy):

    /usr/bin/python3 scripts/reduce_ior.py            # write the table, print report
    /usr/bin/python3 scripts/reduce_ior.py --check    # CI: fail if table is stale
    /usr/bin/python3 scripts/reduce_ior.py --markdown # also print tables for docs
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

ROOT = Path(__file__).resolve().parent.parent
DATA_DIR = ROOT / "data" / "ior"
RII_DIR = DATA_DIR / "refractiveindex.info"
PBRT_DIR = DATA_DIR / "pbrt-v4"
TABLE_PATH = ROOT / "src" / "data" / "metal_table.inc"
SPECTRA_PATH = ROOT / "src" / "data" / "metal_spectra.inc"

# ---------------------------------------------------------------------------
# Sampling choices
# ---------------------------------------------------------------------------

# Spectral grid: 380..780 nm inclusive, every 5 nm (81 samples).
LAMBDA_NM = np.arange(380.0, 780.0 + 0.5, 5.0)

# Angular grid for the fit: 90 incidence angles uniform in mu = cos(theta),
# at the midpoints mu_i = (i + 1/2) / 90.  Uniform in mu is uniform in solid
# angle (d omega = d mu d phi), so 0..60 deg and 60..90 deg get equal weight.
# The midpoints avoid theta = 90 deg, where R = 1 for every material.
N_ANGLES = 90
MU_GRID = (np.arange(N_ANGLES) + 0.5) / N_ANGLES

# Reference angles (degrees) whose spectrally reduced reflectance goes into the
# table for the C++ tests.
REF_ANGLES_DEG = (0.0, 45.0, 80.0)

# Fit bounds and starting points (eta, k).
ETA_BOUNDS = (0.01, 10.0)
K_BOUNDS = (0.0, 15.0)
FIT_STARTS = [(0.2, 3.0), (0.5, 6.0), (1.0, 2.0), (1.5, 4.0), (3.0, 3.0),
              (0.1, 9.0), (2.0, 8.0), (5.0, 1.0)]

# ---------------------------------------------------------------------------
# Data-quality decisions (see data/ior/README.md, which quotes the reference
# data set's README, and docs/metals.md).  Werner et al. 2009 derived n, k
# from reflection electron energy-loss spectra (REELS); for W and Pt they give
# a normal-incidence reflectance well above handbook values.
# ---------------------------------------------------------------------------

# Tungsten: Palik, "Handbook of Optical Constants of Solids" (1985), at 550 nm,
# as quoted in the reference data set's README (data/ior/README.md).  Used as a
# grey (wavelength-independent) constant when Werner's F0 is "far above" Palik's.
PALIK_W_ETA = 3.5
PALIK_W_K = 2.73
# "Far above": Werner's photopic (CIE Y) normal-incidence reflectance exceeds
# Palik's by more than this.
W_REJECT_MARGIN = 0.15

# Platinum: handbook normal-incidence reflectance in the visible.
PT_HANDBOOK_F0 = (0.65, 0.73)
# Werner is kept but marked provisional if its photopic F0 lies outside the
# handbook range by more than this.
PT_PROVISIONAL_MARGIN = 0.05

# ---------------------------------------------------------------------------
# Colour science
# ---------------------------------------------------------------------------


def _piecewise_gaussian(lam, mu, sigma_lo, sigma_hi):
    """g(lambda; mu, s1, s2) of Wyman, Sloan & Shirley 2013, eq. 2:
    a Gaussian with width s1 below the mean and s2 above it."""
    sigma = np.where(lam < mu, sigma_lo, sigma_hi)
    t = (lam - mu) / sigma
    return np.exp(-0.5 * t * t)


def cie1931_cmf(lam):
    """CIE 1931 2-degree colour matching functions x, y, z (rows) at lambda (nm).

    Multi-lobe analytic fit: C. Wyman, P.-P. Sloan, P. Shirley, "Simple
    Analytic Approximations to the CIE XYZ Color Matching Functions",
    Journal of Computer Graphics Techniques 2(2), 2013, equation 2.
    """
    g = _piecewise_gaussian
    x = (1.056 * g(lam, 599.8, 37.9, 31.0) + 0.362 * g(lam, 442.0, 16.0, 26.7)
         - 0.065 * g(lam, 501.1, 20.4, 26.2))
    y = 0.821 * g(lam, 568.8, 46.9, 40.5) + 0.286 * g(lam, 530.9, 16.3, 31.1)
    z = 1.217 * g(lam, 437.0, 11.8, 36.0) + 0.681 * g(lam, 459.0, 26.0, 13.8)
    return np.stack([x, y, z])


# XYZ -> linear sRGB (Rec. ITU-R BT.709 primaries, D65 white), the inverse of
# the sRGB primaries matrix (IEC 61966-2-1), to 7 decimals.
XYZ_TO_LINEAR_SRGB = np.array([
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
])


def trapezoid_weights(x):
    """Quadrature weights of the composite trapezoidal rule on samples x."""
    w = np.zeros_like(x)
    dx = np.diff(x)
    w[:-1] += 0.5 * dx
    w[1:] += 0.5 * dx
    return w


def rgb_weights(lam):
    """Per-channel spectral weights W_c(lambda), shape (3, len(lam)).

    R_c = sum_lambda W_c(lambda) R(lambda) is the white-balanced linear sRGB
    value of a spectral reflectance R(lambda) under the equal-energy
    illuminant E: XYZ = integral R(lambda) cmf(lambda) d lambda, RGB = M XYZ,
    then RGB_c /= RGB_c(white), where white is R(lambda) = 1.  By construction
    sum_lambda W_c = 1 for every channel.  Some W_c are negative at some
    wavelengths (the sRGB gamut does not contain the spectral locus).
    """
    cmf = cie1931_cmf(lam) * trapezoid_weights(lam)   # (3, L): integrals as sums
    per_channel = XYZ_TO_LINEAR_SRGB @ cmf            # (3, L)
    white = per_channel.sum(axis=1, keepdims=True)    # RGB of R(lambda) = 1
    return per_channel / white, white.ravel()


def luminance_weights(lam):
    """Weights giving the photopic (CIE Y) reflectance under illuminant E,
    normalised so that a perfect reflector has Y = 1."""
    y = cie1931_cmf(lam)[1] * trapezoid_weights(lam)
    return y / y.sum()


# ---------------------------------------------------------------------------
# Exact Fresnel reflectance of a conductor
# ---------------------------------------------------------------------------


def fresnel_conductor(cos_i, eta, k):
    """Exact unpolarised reflectance of light going from air (n = 1) into a
    conductor with complex refractive index eta + i k.

    Born & Wolf sec. 14.2; identical to pbrt-v4 FrComplex:
        sin^2 t = sin^2 i / (eta + ik)^2,   cos t = sqrt(1 - sin^2 t)  (complex)
        r_par  = ((eta+ik) cos i - cos t) / ((eta+ik) cos i + cos t)
        r_perp = (cos i - (eta+ik) cos t) / (cos i + (eta+ik) cos t)
        R = (|r_par|^2 + |r_perp|^2) / 2
    Arguments broadcast against each other.
    """
    cos_i = np.clip(np.asarray(cos_i, dtype=float), 0.0, 1.0)
    m = np.asarray(eta, dtype=float) + 1j * np.asarray(k, dtype=float)
    sin2_i = 1.0 - cos_i * cos_i
    sin2_t = sin2_i / (m * m)
    cos_t = np.sqrt(1.0 - sin2_t)
    r_par = (m * cos_i - cos_t) / (m * cos_i + cos_t)
    r_perp = (cos_i - m * cos_t) / (cos_i + m * cos_t)
    return 0.5 * (np.abs(r_par) ** 2 + np.abs(r_perp) ** 2)


def fresnel_conductor_ab(cos_i, eta, k):
    """The same reflectance in the real a^2 b^2 form (as in pbrt-v3's
    FrConductor), used only as a self-check of fresnel_conductor:
        t0 = eta^2 - k^2 - sin^2 i
        a^2 + b^2 = sqrt(t0^2 + 4 eta^2 k^2),   a = sqrt((a^2 + b^2 + t0) / 2)
        Rs = (a^2+b^2 - 2 a cos i + cos^2 i) / (a^2+b^2 + 2 a cos i + cos^2 i)
        Rp = Rs (cos^2 i (a^2+b^2) - 2 a cos i sin^2 i + sin^4 i)
                / (cos^2 i (a^2+b^2) + 2 a cos i sin^2 i + sin^4 i)
        R = (Rs + Rp) / 2
    """
    cos_i = np.clip(np.asarray(cos_i, dtype=float), 0.0, 1.0)
    c2 = cos_i * cos_i
    s2 = 1.0 - c2
    t0 = eta * eta - k * k - s2
    a2b2 = np.sqrt(t0 * t0 + 4.0 * eta * eta * k * k)
    a = np.sqrt(np.maximum(0.5 * (a2b2 + t0), 0.0))
    rs = (a2b2 - 2.0 * a * cos_i + c2) / (a2b2 + 2.0 * a * cos_i + c2)
    t1 = c2 * a2b2 + s2 * s2
    t2 = 2.0 * a * cos_i * s2
    rp = rs * (t1 - t2) / (t1 + t2)
    return 0.5 * (rs + rp)


def self_test_fresnel():
    """The complex and the a^2 b^2 forms must agree to rounding error."""
    rng = np.random.default_rng(1)
    mu = rng.uniform(0.0, 1.0, 2000)
    eta = rng.uniform(0.01, 10.0, 2000)
    k = rng.uniform(0.0, 15.0, 2000)
    d = np.max(np.abs(fresnel_conductor(mu, eta, k) - fresnel_conductor_ab(mu, eta, k)))
    if d > 1e-12:
        sys.exit(f"reduce_ior: Fresnel self-test failed (max difference {d:g})")
    # Normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
    f0 = ((eta - 1) ** 2 + k ** 2) / ((eta + 1) ** 2 + k ** 2)
    d0 = np.max(np.abs(fresnel_conductor(1.0, eta, k) - f0))
    if d0 > 1e-12:
        sys.exit(f"reduce_ior: Fresnel F0 self-test failed (max difference {d0:g})")


# ---------------------------------------------------------------------------
# Data files
# ---------------------------------------------------------------------------


def read_rii_nk(path: Path):
    """Read the 'tabulated nk' block of a refractiveindex.info YAML file.

    Returns (lambda_nm, n, k) sorted by wavelength.  Only the simple layout
    used by the database is supported:
        DATA:
          - type: tabulated nk
            data: |
                <lambda_um> <n> <k>
                ...
    """
    lines = path.read_text(encoding="utf-8").splitlines()
    rows = []
    in_block = False
    seen_type = False
    for line in lines:
        s = line.strip()
        if s.startswith("- type:") or s.startswith("type:"):
            seen_type = s.split(":", 1)[1].strip() == "tabulated nk"
            in_block = False
            continue
        if seen_type and s.startswith("data:"):
            in_block = True
            continue
        if in_block:
            parts = s.split()
            if len(parts) == 3:
                try:
                    rows.append([float(p) for p in parts])
                    continue
                except ValueError:
                    pass
            in_block = False   # end of the block (next key, blank line, ...)
    if not rows:
        raise ValueError(f"{path}: no 'tabulated nk' data found")
    a = np.array(rows)
    a = a[np.argsort(a[:, 0], kind="stable")]
    if np.any(np.diff(a[:, 0]) <= 0):
        raise ValueError(f"{path}: wavelengths are not strictly increasing")
    return a[:, 0] * 1000.0, a[:, 1], a[:, 2]   # micrometres -> nm


def read_pbrt_csv(path: Path):
    """Read a pbrt-v4 named-spectrum CSV ('# comments', then 'lambda_nm,value')."""
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        lam, val = s.split(",")
        rows.append((float(lam), float(val)))
    a = np.array(rows)
    a = a[np.argsort(a[:, 0], kind="stable")]
    if np.any(np.diff(a[:, 0]) <= 0):
        raise ValueError(f"{path}: wavelengths are not strictly increasing")
    return a[:, 0], a[:, 1]


@dataclass
class Spectrum:
    """n, k resampled on LAMBDA_NM, with a note on coverage."""
    n: np.ndarray
    k: np.ndarray
    coverage: str


def resample(lam, values, what):
    """Linear interpolation onto LAMBDA_NM; np.interp clamps to the end values
    outside the data range.  Returns the samples and a coverage note."""
    lo, hi = float(lam[0]), float(lam[-1])
    note = ""
    if lo > LAMBDA_NM[0] or hi < LAMBDA_NM[-1]:
        note = (f"{what}: data {lo:g}..{hi:g} nm does not cover "
                f"{LAMBDA_NM[0]:g}..{LAMBDA_NM[-1]:g} nm, clamped at the ends")
    return np.interp(LAMBDA_NM, lam, values), note


def load_rii(filename):
    path = RII_DIR / filename
    lam, n, k = read_rii_nk(path)
    n_s, note_n = resample(lam, n, filename)
    k_s, _ = resample(lam, k, filename)
    # Count the original samples that fall inside the visible range, as a
    # measure of how much interpolation is going on.
    inside = int(np.sum((lam >= LAMBDA_NM[0]) & (lam <= LAMBDA_NM[-1])))
    cov = note_n or (f"{filename}: data {lam[0]:g}..{lam[-1]:g} nm covers the range, "
                     f"{inside} samples inside 380..780 nm")
    return Spectrum(n_s, k_s, cov)


def load_pbrt(eta_file, k_file):
    lam_n, n = read_pbrt_csv(PBRT_DIR / eta_file)
    lam_k, k = read_pbrt_csv(PBRT_DIR / k_file)
    n_s, note_n = resample(lam_n, n, eta_file)
    k_s, note_k = resample(lam_k, k, k_file)
    inside = int(np.sum((lam_n >= LAMBDA_NM[0]) & (lam_n <= LAMBDA_NM[-1])))
    cov = "; ".join(x for x in (note_n, note_k) if x) or (
        f"{eta_file}/{k_file}: data {lam_n[0]:g}..{lam_n[-1]:g} nm covers the range, "
        f"{inside} samples inside 380..780 nm")
    return Spectrum(n_s, k_s, cov)


def constant_spectrum(eta, k, note):
    return Spectrum(np.full_like(LAMBDA_NM, eta), np.full_like(LAMBDA_NM, k), note)


# ---------------------------------------------------------------------------
# Reduction and fit
# ---------------------------------------------------------------------------

W_RGB, WHITE_RGB = rgb_weights(LAMBDA_NM)
W_Y = luminance_weights(LAMBDA_NM)


def spectral_reflectance(spec: Spectrum, mu):
    """R(lambda, theta), shape (len(mu), len(LAMBDA_NM))."""
    return fresnel_conductor(np.asarray(mu)[:, None], spec.n[None, :], spec.k[None, :])


def reduce_rgb(spec: Spectrum, mu):
    """White-balanced linear sRGB reflectance R_c(theta), shape (len(mu), 3)."""
    return spectral_reflectance(spec, mu) @ W_RGB.T


def reduce_y(spec: Spectrum, mu):
    """Photopic reflectance Y(theta) under illuminant E, shape (len(mu),)."""
    return spectral_reflectance(spec, mu) @ W_Y


def fit_channel(target):
    """Least-squares fit of (eta, k) to a reflectance curve sampled on MU_GRID.

    Several starting points; the solution with the smallest cost wins (ties
    broken by order, so the result is deterministic)."""
    def residual(p):
        return fresnel_conductor(MU_GRID, p[0], p[1]) - target

    best = None
    for x0 in FIT_STARTS:
        r = least_squares(residual, x0, bounds=([ETA_BOUNDS[0], K_BOUNDS[0]],
                                                [ETA_BOUNDS[1], K_BOUNDS[1]]),
                          method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                          max_nfev=2000)
        if best is None or r.cost < best.cost * (1.0 - 1e-9):
            best = r
    return best.x


@dataclass
class Metal:
    name: str
    symbol: str
    source: str
    spectrum: Spectrum
    notes: list = field(default_factory=list)
    # results
    eta: np.ndarray = None
    k: np.ndarray = None
    f0: np.ndarray = None
    r45: np.ndarray = None
    r80: np.ndarray = None
    rms: float = 0.0
    max_err: float = 0.0
    ref_err: float = 0.0
    f0_y: float = 0.0

    def compute(self):
        target = reduce_rgb(self.spectrum, MU_GRID)              # (N_ANGLES, 3)
        ref = reduce_rgb(self.spectrum, np.cos(np.radians(REF_ANGLES_DEG)))
        self.f0, self.r45, self.r80 = ref[0], ref[1], ref[2]
        self.f0_y = float(reduce_y(self.spectrum, [1.0])[0])
        params = np.array([fit_channel(target[:, c]) for c in range(3)])
        self.eta, self.k = params[:, 0], params[:, 1]
        fitted = fresnel_conductor(MU_GRID[:, None], self.eta[None, :], self.k[None, :])
        err = fitted - target
        self.rms = float(np.sqrt(np.mean(err * err)))
        if self.rms < 1e-12:
            self.rms = 0.0   # exact fit (grey constant): don't print rounding noise
        self.max_err = float(np.max(np.abs(err)))
        # Error of the fit at the reference angles (what a C++ test would see
        # comparing Fresnel(eta, k) with the F0/R45/R80 columns).
        mu_ref = np.cos(np.radians(REF_ANGLES_DEG))
        fit_ref = fresnel_conductor(mu_ref[:, None], self.eta[None, :], self.k[None, :])
        self.ref_err = float(np.max(np.abs(fit_ref - ref)))
        if np.any(target < 0.0) or np.any(target > 1.0):
            self.notes.append("reduced R_c(theta) leaves [0, 1] (out-of-gamut spectrum)")
        return self


def build_metals(report):
    """The 12 metals, in table order, with the W and Pt decisions applied."""
    rii, pbrt = load_rii, load_pbrt
    metals = [
        Metal("gold", "Au", "Johnson & Christy 1972 (refractiveindex.info)",
              rii("Au-Johnson.yml")),
        Metal("silver", "Ag", "Johnson & Christy 1972 (refractiveindex.info)",
              rii("Ag-Johnson.yml")),
        Metal("copper", "Cu", "Johnson & Christy 1972 (refractiveindex.info)",
              rii("Cu-Johnson.yml")),
        Metal("aluminium", "Al", "Rakic 1995 (refractiveindex.info)",
              rii("Al-Rakic.yml")),
        Metal("chromium", "Cr", "Johnson & Christy 1974 (refractiveindex.info)",
              rii("Cr-Johnson.yml")),
        Metal("iron", "Fe", "Johnson & Christy 1974 (refractiveindex.info)",
              rii("Fe-Johnson.yml")),
        Metal("nickel", "Ni", "Johnson & Christy 1974 (refractiveindex.info)",
              rii("Ni-Johnson.yml")),
        Metal("titanium", "Ti", "Johnson & Christy 1974 (refractiveindex.info)",
              rii("Ti-Johnson.yml")),
        Metal("platinum", "Pt", "Werner et al. 2009 (refractiveindex.info)",
              rii("Pt-Werner.yml")),
        Metal("tungsten", "W", "Werner et al. 2009 (refractiveindex.info)",
              rii("W-Werner.yml")),
        Metal("zinc", "Zn", "Werner et al. 2009 (refractiveindex.info)",
              rii("Zn-Werner.yml")),
        Metal("brass", "CuZn", "pbrt-v4 named spectrum metal-CuZn",
              pbrt("metal-CuZn-eta.csv", "metal-CuZn-k.csv")),
    ]
    by_name = {m.name: m for m in metals}

    # --- Tungsten: Werner vs Palik -------------------------------------------
    w = by_name["tungsten"]
    werner_w = Metal(w.name, w.symbol, w.source, w.spectrum).compute()
    palik_spec = constant_spectrum(PALIK_W_ETA, PALIK_W_K,
                                   "grey constant, no spectral data")
    palik_f0 = float(reduce_y(palik_spec, [1.0])[0])
    report.append("Tungsten decision:")
    report.append(f"  Werner 2009 reduction: eta = {fmt3(werner_w.eta)}, k = {fmt3(werner_w.k)}, "
                  f"F0 RGB = {fmt3(werner_w.f0)}, F0 (CIE Y) = {werner_w.f0_y:.4f}, "
                  f"fit RMS = {werner_w.rms:.2e}")
    report.append(f"  Palik n = {PALIK_W_ETA}, k = {PALIK_W_K} (550 nm): F0 = {palik_f0:.4f}")
    if werner_w.f0_y - palik_f0 > W_REJECT_MARGIN:
        w.spectrum = palik_spec
        w.source = (f"Palik 1985 grey constant n={PALIK_W_ETA} k={PALIK_W_K} at 550 nm; "
                    f"Werner 2009 rejected (F0 {werner_w.f0_y:.2f} vs {palik_f0:.2f})")
        report.append(f"  -> Werner F0 exceeds Palik's by {werner_w.f0_y - palik_f0:.3f} "
                      f"> {W_REJECT_MARGIN}: using the Palik grey constant.")
    else:
        report.append("  -> Werner agrees with Palik within the margin: keeping Werner.")

    # --- Platinum: Werner vs handbook range --------------------------------
    p = by_name["platinum"]
    p.compute()
    lo, hi = PT_HANDBOOK_F0
    off = max(lo - p.f0_y, p.f0_y - hi, 0.0)
    report.append("Platinum decision:")
    report.append(f"  Werner 2009 F0 RGB = {fmt3(p.f0)}, F0 (CIE Y) = {p.f0_y:.4f}; "
                  f"handbook visible F0 ~ {lo}..{hi}")
    if off > PT_PROVISIONAL_MARGIN:
        p.source = (f"Werner et al. 2009 (refractiveindex.info), provisional: "
                    f"F0 {p.f0_y:.2f} above handbook {lo}-{hi}")
        report.append(f"  -> {off:.3f} outside the handbook range (> {PT_PROVISIONAL_MARGIN}): "
                      "kept, marked provisional.")
    else:
        report.append("  -> within the margin of the handbook range: kept as is.")

    for m in metals:
        if m.eta is None:
            m.compute()
    return metals


# ---------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------


def fmt3(v, spec=".4f"):
    return "(" + ", ".join(format(float(x), spec) for x in v) + ")"


def num(x):
    """9 significant digits; '-0' normalised to '0'."""
    s = f"{float(x):.9g}"
    return "0" if s == "-0" else s


def vec(v):
    return "{" + ", ".join(num(x) for x in v) + "}"


def c_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def render_table(metals):
    out = [
        "// GENERATED by scripts/reduce_ior.py -- DO NOT EDIT.",
        "// Regenerate: /usr/bin/python3 scripts/reduce_ior.py ; check: --check",
        "// Method: docs/metals.md.  Data: data/ior/ (see data/ior/README.md).",
        "//",
        "// One row per metal:",
        "//   {name, symbol, {eta_r, eta_g, eta_b}, {k_r, k_g, k_b},",
        "//    {F0_r, F0_g, F0_b}, {R45_r, R45_g, R45_b}, {R80_r, R80_g, R80_b},",
        "//    source, rms_err},",
        "// eta, k: per-channel fit of the exact conductor Fresnel curve to the",
        "//   spectrally reduced reflectance (90 angles uniform in cos theta).",
        "// F0, R45, R80: spectrally reduced reflectance at 0, 45, 80 degrees",
        "//   (linear sRGB, CIE 1931 2-deg, illuminant E, white-balanced so that",
        "//   R(lambda) = 1 gives (1, 1, 1)); reference values for tests.",
        "// rms_err: RMS of (fitted - reduced) over the angle grid and channels.",
    ]
    for m in metals:
        out.append("{" + ", ".join([
            c_string(m.name), c_string(m.symbol), vec(m.eta), vec(m.k),
            vec(m.f0), vec(m.r45), vec(m.r80), c_string(m.source), num(m.rms),
        ]) + "},")
    return "\n".join(out) + "\n"


def render_spectra(metals):
    """n and k of step 2 (LAMBDA_NM), one row per metal in table order."""
    out = [
        "// GENERATED by scripts/reduce_ior.py -- DO NOT EDIT.",
        "// Regenerate: /usr/bin/python3 scripts/reduce_ior.py ; check: --check",
        "// Method: docs/metals.md, step 2.  Data: data/ior/ (see data/ior/README.md).",
        "//",
        f"// One row per metal, in the order of metal_table.inc: {{name, {{n}}, {{k}}}},",
        f"// n and k linearly interpolated onto {LAMBDA_NM[0]:g}..{LAMBDA_NM[-1]:g} nm every "
        f"{LAMBDA_NM[1] - LAMBDA_NM[0]:g} nm ({len(LAMBDA_NM)} samples).",
    ]
    for m in metals:
        out.append("{" + ", ".join([c_string(m.name), vec(m.spectrum.n), vec(m.spectrum.k)]) + "},")
    return "\n".join(out) + "\n"


def numbers_equal(a: str, b: str, rel=1e-6, abs_=1e-9):
    """Compare two renderings token by token: text must match exactly, numbers
    within a tolerance (last-digit noise from a different numpy/scipy/BLAS)."""
    tok = re.compile(r"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?|\s+|.")
    ta, tb = tok.findall(a), tok.findall(b)
    if len(ta) != len(tb):
        return False
    for x, y in zip(ta, tb):
        if x == y:
            continue
        try:
            fx, fy = float(x), float(y)
        except ValueError:
            return False
        if abs(fx - fy) > abs_ + rel * max(abs(fx), abs(fy)):
            return False
    return True


def markdown(metals):
    lines = [
        "| metal | source | eta (R, G, B) | k (R, G, B) | F0 (R, G, B) | fit RMS | fit max |",
        "|---|---|---|---|---|---|---|",
    ]
    for m in metals:
        lines.append(f"| {m.name} | {m.source} | {fmt3(m.eta, '.3f')} | {fmt3(m.k, '.3f')} | "
                     f"{fmt3(m.f0, '.3f')} | {m.rms:.1e} | {m.max_err:.1e} |")
    return "\n".join(lines)


def gold_extras(metals, report):
    """Numbers quoted in docs/metals.md: gold skin depth and Schlick comparison."""
    gold = next(m for m in metals if m.name == "gold")
    i550 = int(np.argmin(np.abs(LAMBDA_NM - 550.0)))
    n550, k550 = gold.spectrum.n[i550], gold.spectrum.k[i550]
    depth = 550.0 / (4.0 * math.pi * k550)
    report.append(f"Gold at 550 nm: n = {n550:.4f}, k = {k550:.4f}; "
                  f"intensity penetration depth lambda/(4 pi k) = {depth:.2f} nm "
                  f"(amplitude depth lambda/(2 pi k) = {2 * depth:.2f} nm)")
    f0_fit = fresnel_conductor(1.0, gold.eta, gold.k)
    report.append(f"Gold F0 of the fitted (eta, k) = {fmt3(f0_fit)}; "
                  f"spectral F0 = {fmt3(gold.f0)}")
    report.append("Gold: Schlick F0 + (1 - F0)(1 - cos)^5 with the fitted F0 vs exact Fresnel "
                  "of the fitted (eta, k) vs spectral reduction:")
    for deg in (60.0, 80.0, 85.0):
        mu = math.cos(math.radians(deg))
        schlick = f0_fit + (1.0 - f0_fit) * (1.0 - mu) ** 5
        exact = fresnel_conductor(mu, gold.eta, gold.k)
        spectral = reduce_rgb(gold.spectrum, [mu])[0]
        report.append(f"  {deg:4.0f} deg: Schlick {fmt3(schlick)}  exact-fit {fmt3(exact)}  "
                      f"spectral {fmt3(spectral)}  Schlick-exact {fmt3(schlick - exact, '+.4f')}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true",
                    help="recompute and exit 1 if src/data/metal_table.inc or metal_spectra.inc is out of date")
    ap.add_argument("--markdown", action="store_true",
                    help="also print the results table in Markdown (for docs/metals.md)")
    args = ap.parse_args(argv)

    self_test_fresnel()
    report = []
    metals = build_metals(report)
    text = render_table(metals)

    spectra = render_spectra(metals)
    if args.check:
        stale = 0
        for path, expected in ((TABLE_PATH, text), (SPECTRA_PATH, spectra)):
            rel = path.relative_to(ROOT)
            if not path.exists():
                print(f"reduce_ior --check: {rel} is missing; run scripts/reduce_ior.py", file=sys.stderr)
                stale = 1
                continue
            current = path.read_text(encoding="utf-8")
            if current == expected:
                print(f"reduce_ior --check: {rel} is up to date")
            elif numbers_equal(current, expected):
                print(f"reduce_ior --check: {rel} is up to date "
                      "(differs only in last-digit floating-point noise)")
            else:
                print(f"reduce_ior --check: {rel} is out of date; "
                      "run /usr/bin/python3 scripts/reduce_ior.py and commit the result",
                      file=sys.stderr)
                stale = 1
        return stale

    TABLE_PATH.parent.mkdir(parents=True, exist_ok=True)
    TABLE_PATH.write_text(text, encoding="utf-8")
    SPECTRA_PATH.write_text(spectra, encoding="utf-8")

    print(f"wrote {TABLE_PATH.relative_to(ROOT)} and {SPECTRA_PATH.relative_to(ROOT)}")
    print(f"white (R = 1) linear sRGB before normalisation: {fmt3(WHITE_RGB)}")
    print("Coverage:")
    for m in metals:
        print(f"  {m.name:10s} {m.spectrum.coverage}")
    for line in report:
        print(line)
    gold_lines = []
    gold_extras(metals, gold_lines)
    for line in gold_lines:
        print(line)
    print("Results (eta, k fitted; F0/R45/R80 spectral):")
    for m in metals:
        print(f"  {m.name:10s} eta {fmt3(m.eta)} k {fmt3(m.k)} F0 {fmt3(m.f0)} "
              f"R45 {fmt3(m.r45)} R80 {fmt3(m.r80)} rms {m.rms:.2e} max {m.max_err:.2e} "
              f"ref-angle err {m.ref_err:.2e} "
              f"F0(Y) {m.f0_y:.4f}" + (f"  NOTE: {'; '.join(m.notes)}" if m.notes else ""))
    if args.markdown:
        print()
        print(markdown(metals))
    return 0


if __name__ == "__main__":
    sys.exit(main())
