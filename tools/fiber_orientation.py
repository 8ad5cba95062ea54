#!/usr/bin/python3
"""Fiber orientation: angle against position and the orientation tensor per
region (paper Fig. 12: fibers near the walls align with the flow, the core
is more random).

Reads /dem/position and /dem/fiber of a sphdem run's snapshots (an output
directory, its .xdmf index or one .h5 file). For each fiber:

  p      = unit end-to-end vector (last minus first particle of the fiber,
           in global-id order), sign fixed so p_x >= 0 (a fiber has no head)
  theta  = atan2(p_y, p_x) in degrees, in (-90, 90]; 0 = along x, the
           plate arms' flow direction
  c      = centroid, the mean of its particles' positions

and for each region R (a union of boxes; a fiber belongs to R when c does):

  a_ij = <p_i p_j> = (1/N_R) sum_{fibers in R} p_i p_j      (a_xx + a_yy = 1)

a_xx = 1: all along x; a_yy = 1: all along y; a_xx = a_yy = 0.5, a_xy = 0:
random in the plane (or two symmetric families).

Default regions (mm; the plate's arms y in [-4, 0] away from the gate
|x| > 3, also the horizontal part of the corners and branches molds):
  left_wall   x < -3, within 1 mm of y = 0 or y = -4
  left_core   x < -3, -3 <= y <= -1
  right_wall, right_core   the same for x > 3
--band, --gate-half-width and --wall-distance change them; --region
replaces them: NAME:XMIN,XMAX,YMIN,YMAX in mm (inf allowed), repeat a NAME
to add boxes to it.

Prints N, a_xx, a_xy, a_yy and the mean |theta| per region and time
(--csv writes them). The PNG (-o) shows theta against the centroid's y
(or x with --across x) for the fibers in the regions, the mean |theta| per
bin, and a_xx per region.

examples:
  tools/fiber_orientation.py out/plate_fibers_3.8 --time 0.12 -o fig12.png
  tools/fiber_orientation.py out/corners_fibers_3.8 --region leg:20,24,-20,-4 --across x
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402

HEADER = ["time", "region", "fibers", "a_xx", "a_xy", "a_yy", "mean_abs_angle_deg"]


def default_regions(band=(-4.0, 0.0), gate_half_width=3.0, wall_distance=1.0):
    y0, y1 = band
    g, w = gate_half_width, wall_distance
    specs = []
    for side, (x0, x1) in (("left", (-np.inf, -g)), ("right", (g, np.inf))):
        specs += ["%s_wall:%g,%g,%g,%g" % (side, x0, x1, y1 - w, y1),
                  "%s_wall:%g,%g,%g,%g" % (side, x0, x1, y0, y0 + w),
                  "%s_core:%g,%g,%g,%g" % (side, x0, x1, y0 + w, y1 - w)]
    return io.parse_regions(specs)


def angles(p):
    """Angle of each direction from +x in degrees, folded into (-90, 90]."""
    theta = np.degrees(np.arctan2(p[:, 1], p[:, 0]))
    theta = np.where(theta > 90, theta - 180, theta)
    return np.where(theta <= -90, theta + 180, theta)


def orientation_tensor(p):
    """a_ij = <p_i p_j> of the unit vectors p (n, 2); NaN for n = 0."""
    if len(p) == 0:
        return np.full((2, 2), np.nan)
    return np.einsum("ni,nj->ij", p, p) / len(p)


def analyse(fibers, regions):
    """Per region: (count, a (2x2), mean |theta| [deg]); and the per-fiber
    centroids, directions and angles (NaN-direction fibers dropped)."""
    c = fibers.centroids()
    p = fibers.directions()
    ok = np.all(np.isfinite(p), axis=1)
    c, p = c[ok], p[ok]
    th = angles(p)
    result = []
    for r in regions:
        inside = r.contains(c)
        n = int(np.count_nonzero(inside))
        result.append((r, n, orientation_tensor(p[inside]),
                       float(np.mean(np.abs(th[inside]))) if n else np.nan))
    return result, c, p, th


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("--region", action="append", metavar="NAME:XMIN,XMAX,YMIN,YMAX",
                    help="a region box in mm (inf allowed); repeat; replaces the defaults")
    ap.add_argument("--band", nargs=2, type=float, default=[-4.0, 0.0], metavar=("Y0", "Y1"),
                    help="default regions: the arm's y range [mm] (default -4 0)")
    ap.add_argument("--gate-half-width", type=float, default=3.0,
                    help="default regions: |x| [mm] beyond which the arms start (default 3)")
    ap.add_argument("--wall-distance", type=float, default=1.0,
                    help="default regions: width [mm] of the near-wall layers (default 1)")
    ap.add_argument("--across", choices=["x", "y"], default="y",
                    help="coordinate of the angle plot (default y: across the plate arm)")
    ap.add_argument("--bins", type=int, default=8, help="bins of the mean |theta| curve (default 8)")
    ap.add_argument("--csv", help="write the per-region table to this CSV file")
    ap.add_argument("-o", "--output", default="fiber_orientation.png",
                    help="PNG to write (default fiber_orientation.png)")
    a = ap.parse_args()

    regions = io.parse_regions(a.region) if a.region else \
        default_regions(a.band, a.gate_half_width, a.wall_distance)
    snaps = [io.Snapshot(r) for r in io.snapshots_from_args(a)]
    rows, plots = [], []
    print("regions (mm): " + "; ".join("%s = %s" % (r.name, r.describe()) for r in regions))
    print("%-10s %-14s %7s %8s %8s %8s %10s" % ("t [s]", "region", "fibers", "a_xx", "a_xy", "a_yy",
                                              "|theta|deg"))
    for s in snaps:
        fibers = s.fibers()
        result, c, p, th = analyse(fibers, regions)
        for r, n, t, mean_abs in result:
            print("%-10.5g %-14s %7d %8.4f %8.4f %8.4f %10.2f" % (s.time, r.name, n, t[0, 0], t[0, 1],
                                                                t[1, 1], mean_abs))
            rows.append((s.time, r.name, n, t[0, 0], t[0, 1], t[1, 1], mean_abs))
        inside = np.zeros(len(c), bool)
        for r in regions:
            inside |= r.contains(c)
        plots.append((s, c[inside], th[inside], result))
    if a.csv:
        io.write_csv(a.csv, HEADER, rows)

    plt = io.pyplot()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw=dict(width_ratios=[1.6, 1]))
    k = 1 if a.across == "y" else 0
    for i, (s, c, th, result) in enumerate(plots):
        color = "C%d" % (i % 10)
        ax.plot(c[:, k] / MM, th, ".", color=color, ms=4, alpha=0.6)
        if len(c):
            edges = np.linspace(c[:, k].min(), c[:, k].max(), a.bins + 1)
            idx = np.clip(np.digitize(c[:, k], edges) - 1, 0, a.bins - 1)
            mid, mean = [], []
            for b in range(a.bins):
                if np.any(idx == b):
                    mid.append(0.5 * (edges[b] + edges[b + 1]) / MM)
                    mean.append(np.mean(np.abs(th[idx == b])))
            ax.plot(mid, mean, "-o", color=color, ms=4, label="t = %.4g s: mean |theta| (%d fibers)"
                    % (s.time, len(c)))
        names = [r.name for r, *_ in result]
        axx = [t[0, 0] for _, _, t, _ in result]
        width = 0.8 / len(plots)
        ax2.bar(np.arange(len(names)) + i * width, axx, width, color=color, label="t = %.4g s" % s.time)
    ax.axhline(0, color="0.5", lw=0.5)
    ax.set_ylim(-92, 92)
    ax.set_yticks([-90, -45, 0, 45, 90])
    ax.set_xlabel("fiber centroid %s [mm]" % a.across)
    ax.set_ylabel("fiber angle from x [deg]")
    ax.set_title("%s: fibers in the regions" % snaps[0].case, fontsize=10)
    ax.legend(fontsize=8)
    ax2.set_xticks(np.arange(len(regions)) + 0.4 - 0.4 / len(plots))
    ax2.set_xticklabels([r.name for r in regions], rotation=30, ha="right")
    ax2.axhline(0.5, color="0.5", ls=":", lw=0.8)
    ax2.set_ylim(0, 1)
    ax2.set_ylabel("a_xx = <p_x p_x>  (1: along x)")
    ax2.set_title("orientation tensor per region", fontsize=10)
    ax2.legend(fontsize=8)
    fig.savefig(a.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
