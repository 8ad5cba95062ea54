#!/usr/bin/python3
"""Real-melt figures (issue 13; docs/paper-comparison.md "The real melt"):
temperature and viscosity maps of the resin and the velocity profile across
a plate arm, at the chosen snapshot times.

Reads /fluid/position, /fluid/temperature, /fluid/viscosity, /fluid/velocity
(and /fluid/frozen when written) and the fibers of a sphdem run's snapshots
(an output directory, its .xdmf index or one .h5 file): a run with
`resin.thermal` and `output.fields` naming temperature and viscosity, e.g.
inputs/plate_melt_pp.yaml. For each time it draws one row: the temperature
map [K] (fibers in black), the viscosity map on a log scale [Pa s], and the
profile of u_x across the arm at x = --x (the resin within --width / 2,
binned in --bins bins over --span), and prints

  peak/mean   the largest bin mean over the mean of the bins (plane
              Poiseuille flow of a Newtonian fluid: 1.5; a plug: towards 1)
  frozen      the fraction of the resin below its no-flow temperature
  T, eta      the range of the resin's temperature and viscosity

A time at which the strip holds no resin yet prints "no resin at the strip"
for the profile and still draws the maps.

examples:
  tools/melt_maps.py out/plate_melt_pp --time 0.005 --time 0.01 -o melt.png
  tools/melt_maps.py out/plate_melt_pp --x 20 --span -4 0 --bins 13 --csv profile.csv
  tools/melt_maps.py out/plate_melt_pp --time 0.12 --xlim -41 41 --ylim -5 6 --dpi 70 -o plate.png
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402
from velocity_profile import bin_profile, strip  # noqa: E402

HEADER = ["time", "y_mm", "u_mean", "count"]


def peak_over_mean(u):
    """Largest bin mean over the mean of the bins (equal bins across the gap)."""
    mean = float(np.mean(u))
    return float(np.max(u)) / mean if mean > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("--x", type=float, default=-20.0, help="strip centre x [mm] (default -20: the left arm)")
    ap.add_argument("--width", type=float, default=2.0, help="strip width [mm] (default 2)")
    ap.add_argument("--span", nargs=2, type=float, default=[-4.0, 0.0], metavar=("Y0", "Y1"),
                    help="across range to bin [mm] (default -4 0: the plate's gap)")
    ap.add_argument("--bins", type=int, default=12, help="bins across the gap (default 12)")
    ap.add_argument("--tmin", type=float, help="lower end of the temperature colours [K] (default the data's)")
    ap.add_argument("--csv", help="write the profile bins to this CSV file")
    ap.add_argument("--xlim", nargs=2, type=float, metavar=("X0", "X1"), help="map x range [mm] (default all)")
    ap.add_argument("--ylim", nargs=2, type=float, metavar=("Y0", "Y1"), help="map y range [mm] (default all)")
    ap.add_argument("--dpi", type=int, default=110, help="PNG resolution (default 110)")
    ap.add_argument("-o", "--output", default="melt_maps.png", help="PNG to write (default melt_maps.png)")
    a = ap.parse_args()
    snaps = [io.Snapshot(r) for r in io.snapshots_from_args(a)]
    span = (a.span[0] * MM, a.span[1] * MM)

    plt = io.pyplot()
    from matplotlib.colors import LogNorm
    zoom = a.xlim is not None or a.ylim is not None
    fig, axes = plt.subplots(len(snaps), 3, figsize=(16, (2.2 if zoom else 3.4) * len(snaps)), squeeze=False,
                             gridspec_kw={"width_ratios": [1.4, 1.4, 1]})
    rows = []
    print("%-9s %8s %9s %9s %10s %10s %8s" % ("t [s]", "frozen", "T min", "T max", "eta min", "eta max",
                                             "peak/mean"))
    for k, s in enumerate(snaps):
        if "fluid" not in s.sets:
            raise io.ToolError("%s: no resin (/fluid) at t = %g s" % (s.path, s.time))
        x, temp = s.fluid("temperature")
        _, eta = s.fluid("viscosity")
        frozen = s.read("fluid/frozen", required=False)
        fibers = s.fibers(required=False)
        for ax, values, label, kw in (
                (axes[k][0], temp, "temperature [K]", dict(cmap="coolwarm", vmin=a.tmin)),
                (axes[k][1], eta, "viscosity [Pa s]",
                 dict(cmap="viridis", norm=LogNorm(vmin=max(float(np.min(eta)), 1e-3), vmax=float(np.max(eta)))))):
            io.draw_mold(ax, s)
            sc = ax.scatter(x[:, 0] / MM, x[:, 1] / MM, c=values, s=0.6, linewidths=0, rasterized=True, **kw)
            if fibers is not None:
                io.draw_fibers(ax, fibers, lw=0.8)
            fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
            ax.set_aspect("equal")
            if a.xlim:
                ax.set_xlim(*a.xlim)
            if a.ylim:
                ax.set_ylim(*a.ylim)
            ax.set_title("%s, t = %.4f s" % (s.case, s.time), fontsize=9)
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
        _, v = s.fluid("velocity")
        sc_, u = strip(x, v, a.x * MM, a.width * MM, "y")
        yb, ub, nb = bin_profile(sc_, u, a.bins, span)
        ax = axes[k][2]
        ratio = float("nan")
        if len(yb) >= 3:
            ratio = peak_over_mean(ub)
            ax.plot(ub, yb / MM, "o-", ms=4, label="peak/mean %.3f" % ratio)
            rows += [(s.time, yb[i] / MM, ub[i], nb[i]) for i in range(len(yb))]
            ax.legend(fontsize=8)
        else:
            ax.text(0.5, 0.5, "no resin at the strip", transform=ax.transAxes, ha="center")
        ax.set_xlabel("u_x [m/s] at x = %g mm" % a.x)
        ax.set_ylabel("y [mm]")
        ax.grid(alpha=0.3)
        frac = float(np.mean(frozen > 0.5)) if frozen is not None and len(frozen) else 0.0
        print("%-9.5g %8.4f %9.2f %9.2f %10.4g %10.4g %8s" % (
            s.time, frac, np.min(temp), np.max(temp), np.min(eta), np.max(eta),
            "%.3f" % ratio if np.isfinite(ratio) else "no resin"))
    if a.csv:
        io.write_csv(a.csv, HEADER, rows)
    fig.tight_layout()
    fig.savefig(a.output, dpi=a.dpi, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
