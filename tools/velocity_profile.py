#!/usr/bin/python3
"""Resin velocity profile across a plate arm, with a fitted parabola (the
paper's "parabolic profiles", Figs. 7-8).

Reads /fluid/position and /fluid/velocity of a sphdem run's snapshots (an
output directory, its .xdmf index or one .h5 file). Takes the resin
particles in a strip of width --width around x = --x (a horizontal arm:
the profile is u_x against y) or around y = --y (a vertical arm, e.g. the
corners mold's legs: u_y against x), bins them by the across coordinate s
(--bins bins over the strip's particles, or over --span), and averages the
along-arm velocity u in each bin (bins with fewer than --min-count
particles are left out; a time with fewer than 3 bins is skipped). It fits

  u(s) = c2 s^2 + c1 s + c0          (least squares on the bin means)
  R^2  = 1 - sum (u_k - u(s_k))^2 / sum (u_k - mean u)^2

and prints c2 [1/(m s)], the vertex s* = -c1 / (2 c2), the peak u(s*), the
mean of the bins, peak/mean (plane Poiseuille flow between walls: 1.5,
c2 = -4 u_peak / H^2 for a gap H), the parabola's zero-crossing width and
R^2. --csv writes the bins (time, s, u, count, fit); the PNG (-o) draws
the bin means and the fits, one colour per time.

examples:
  tools/velocity_profile.py out/plate --x -20 --time 0.06 -o profile.png
  tools/velocity_profile.py out/plate --x 20 --time 0.04 --time 0.08 --span -4 0 --bins 13
  tools/velocity_profile.py out/corners_fibers_3.8 --y -8 --span 20 24 --time 0.08
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402

HEADER = ["time", "s_mm", "u_mean", "count", "u_fit"]


def bin_profile(s, u, bins, span=None, min_count=2):
    """Mean of u in `bins` equal bins of s over span (default s's range).
    Returns (mean s per bin, mean u per bin, count per bin) for the bins
    with at least min_count samples."""
    if len(s) == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, int)
    lo, hi = span if span is not None else (float(np.min(s)), float(np.max(s)))
    keep = (s >= lo) & (s <= hi)
    s, u = s[keep], u[keep]
    edges = np.linspace(lo, hi, bins + 1)
    idx = np.clip(np.digitize(s, edges) - 1, 0, bins - 1)
    n = np.bincount(idx, minlength=bins)
    ok = n >= max(min_count, 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        sm = np.bincount(idx, s, bins) / n
        um = np.bincount(idx, u, bins) / n
    return sm[ok], um[ok], n[ok]


def fit_parabola(s, u):
    """Least-squares u = c2 s^2 + c1 s + c0; returns a dict with c2, c1, c0,
    r2, vertex, peak, mean, ratio (peak / mean) and width (distance between
    the zero crossings, NaN when there are none)."""
    if len(s) < 3:
        raise io.ToolError("only %d bins with resin in the strip: need 3 to fit a parabola "
                           "(check --x/--y, --width and the time)" % len(s))
    c2, c1, c0 = np.polyfit(s, u, 2)
    f = np.polyval([c2, c1, c0], s)
    ss_tot = float(np.sum((u - np.mean(u)) ** 2))
    r2 = 1.0 - float(np.sum((u - f) ** 2)) / ss_tot if ss_tot > 0 else (1.0 if np.allclose(u, f) else 0.0)
    vertex = -c1 / (2 * c2) if c2 != 0 else np.nan
    peak = np.polyval([c2, c1, c0], vertex) if c2 != 0 else np.nan
    disc = c1 * c1 - 4 * c2 * c0
    width = np.sqrt(disc) / abs(c2) if c2 != 0 and disc >= 0 else np.nan
    mean = float(np.mean(u))
    return dict(c2=float(c2), c1=float(c1), c0=float(c0), r2=r2, vertex=float(vertex), peak=float(peak),
                mean=mean, ratio=float(peak / mean) if mean != 0 else np.nan, width=float(width))


def strip(x, v, at, width, across):
    """(s, u) of the particles within width/2 of x = at (across = y) or
    y = at (across = x)."""
    k_along = 0 if across == "y" else 1
    k_across = 1 - k_along
    inside = np.abs(x[:, k_along] - at) <= 0.5 * width
    return x[inside, k_across], v[inside, k_along]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--x", type=float, help="strip centre x [mm]: profile u_x(y) (default -20)")
    where.add_argument("--y", type=float, help="strip centre y [mm]: profile u_y(x) (a vertical arm)")
    ap.add_argument("--width", type=float, default=2.0, help="strip width [mm] (default 2)")
    ap.add_argument("--span", nargs=2, type=float, metavar=("S0", "S1"),
                    help="across range to bin [mm] (default the strip's particles; the plate: -4 0)")
    ap.add_argument("--bins", type=int, default=12, help="bins across the strip (default 12)")
    ap.add_argument("--min-count", type=int, default=2, help="fewest particles in a bin used (default 2)")
    ap.add_argument("--csv", help="write the bins and fitted values to this CSV file")
    ap.add_argument("-o", "--output", default="velocity_profile.png",
                    help="PNG to write (default velocity_profile.png)")
    a = ap.parse_args()
    across = "x" if a.y is not None else "y"
    at = (a.y if a.y is not None else (a.x if a.x is not None else -20.0)) * MM
    span = tuple(v * MM for v in a.span) if a.span else None

    snaps = [io.Snapshot(r) for r in io.snapshots_from_args(a)]
    results, csv_rows, skipped = [], [], []
    comp = "u_x" if across == "y" else "u_y"
    print("strip %s = %g mm, width %g mm: %s against %s" % ("x" if across == "y" else "y", at / MM, a.width,
                                                          comp, across))
    print("%-10s %6s %14s %10s %10s %10s %8s %10s %9s" % ("t [s]", "bins", "c2 [1/(m s)]", "vertex",
                                                         "peak", "mean", "peak/mean", "width", "R^2"))
    print("%-10s %6s %14s %10s %10s %10s %8s %10s %9s" % ("", "", "", "[mm]", "[m/s]", "[m/s]", "", "[mm]", ""))
    for s in snaps:
        x, v = s.fluid("velocity")
        sc, u = strip(x, v, at, a.width * MM, across)
        sb, ub, nb = bin_profile(sc, u, a.bins, span, a.min_count)
        try:
            fit = fit_parabola(sb, ub)
        except io.ToolError as e:  # an empty strip at one time: skip it, fail if all are
            skipped.append("t = %g s: %s" % (s.time, e))
            print("velocity_profile.py: skipped " + skipped[-1], file=sys.stderr)
            continue
        results.append((s, sb, ub, fit))
        print("%-10.5g %6d %14.6g %10.4f %10.5g %10.5g %8.4f %10.4f %9.5f"
              % (s.time, len(sb), fit["c2"], fit["vertex"] / MM, fit["peak"], fit["mean"], fit["ratio"],
                 fit["width"] / MM, fit["r2"]))
        fitted = np.polyval([fit["c2"], fit["c1"], fit["c0"]], sb)
        csv_rows += [(s.time, sb[i] / MM, ub[i], nb[i], fitted[i]) for i in range(len(sb))]
    if not results:
        raise io.ToolError(skipped[-1])
    if a.csv:
        io.write_csv(a.csv, HEADER, csv_rows)

    plt = io.pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, (s, sb, ub, fit) in enumerate(results):
        color = "C%d" % (i % 10)
        ax.plot(sb / MM, ub, "o", color=color, ms=4, label="t = %.4g s" % s.time)
        ss = np.linspace(sb.min(), sb.max(), 100)
        ax.plot(ss / MM, np.polyval([fit["c2"], fit["c1"], fit["c0"]], ss), "-", color=color, lw=1,
                label="parabola, R^2 = %.4f" % fit["r2"])
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_xlabel("%s [mm]" % across)
    ax.set_ylabel("%s [m/s] (mean per bin)" % comp)
    ax.set_title("%s: %s across the strip %s = %g mm (width %g mm)"
                 % (snaps[0].case, comp, "x" if across == "y" else "y", at / MM, a.width), fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(a.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
