#!/usr/bin/env python3
"""Polar lobes of Ward, Ashikhmin-Shirley and matte steel in the plane of incidence.

Light arrives from theta_i = 45 degrees; the plot shows f(wi, wo) cos(theta_i) (reflected radiance
under a unit directional light, luminance) for viewing directions wo in the plane of incidence,
each curve scaled to its own peak (given in the legend). Left: the plane of incidence contains the
tangent t (phi = 0); right: the bitangent b (phi = 90 degrees). Ward and Ashikhmin-Shirley are
given matching anisotropic lobes (alpha = sqrt(2 / (n + 2)): n_u = 100, n_v = 10 is alpha_x = 0.14,
alpha_y = 0.41), so the lobe is narrow in the t plane and wide in the b plane; matte steel is the
isotropic Lafortune fit of pbrt-v1.

    MPLBACKEND=Agg PYTHONPATH=build/release/python /usr/bin/python3 examples/python/polar_lobes.py -o lobes.png
"""
import argparse

import matplotlib.pyplot as plt
import numpy as np

import aniso

MATERIALS = {
    "Ward (alpha 0.14 x 0.41)": aniso.ward(kd=0.1, ks=0.4, alpha_x=0.14, alpha_y=0.41),
    "Ashikhmin-Shirley (n 100 x 10)": aniso.ashikhmin_shirley(rd=0.1, rs=0.05, n_u=100, n_v=10),
    "matte steel (Lafortune)": aniso.Material("matte-steel"),
}
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="polar_lobes.png")
    ap.add_argument("--theta-deg", type=float, default=45.0, help="angle of incidence")
    args = ap.parse_args()

    theta_i = np.radians(args.theta_deg)
    # Viewing angles across the plane: negative on the side the light comes from.
    theta_o = np.radians(np.linspace(-89.5, 89.5, 1433))
    fig, axes = plt.subplots(1, 2, subplot_kw={"projection": "polar"}, figsize=(12, 5.2))
    fig.subplots_adjust(left=0.03, right=0.97, bottom=0.0, top=0.98, wspace=0.12)
    for ax, phi, plane in zip(axes, [0.0, np.pi / 2], ["t (phi = 0)", "b (phi = 90 deg)"]):
        wi = aniso.direction(theta_i, phi + np.pi)  # light on the far side: the mirror direction is at +theta_i
        wo = aniso.direction(np.abs(theta_o), np.where(theta_o >= 0, phi, phi + np.pi))
        peaks = []
        for label, m in MATERIALS.items():
            radiance = m.eval(wi, wo) @ LUMINANCE * np.cos(theta_i)
            peak = radiance.max()
            peaks.append(f"{peak:.3g}")
            ax.plot(theta_o, radiance / peak, label=label, lw=1.8)
        ax.annotate("", xy=(-theta_i, 1.05), xytext=(0, 0), arrowprops={"arrowstyle": "<-", "color": "0.3"})
        ax.text(-theta_i, 1.12, "light", ha="center", color="0.3")
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        ax.set_thetamin(-90)
        ax.set_thetamax(90)
        ax.set_rlim(0, 1.2)
        ax.set_rticks([0.5, 1.0])
        ax.set_title(f"plane of incidence through {plane}\npeaks: " + ", ".join(peaks), y=0.84, fontsize=11)
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=10, frameon=False, bbox_to_anchor=(0.5, 0.12))
    fig.text(0.5, 0.07, f"f(wi, wo) cos(theta_i), luminance, light at {args.theta_deg:g} deg; each curve scaled to its peak (in sr^-1, listed per panel)",
             ha="center", fontsize=11)
    fig.savefig(args.output, dpi=110, bbox_inches="tight")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
