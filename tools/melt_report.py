#!/usr/bin/python3
"""The real-melt plate's validation numbers (issue 13; docs/paper-comparison.md
"The real melt"): the fill, the profile across the arms at several stations,
the frozen layers, the fibers' orientation per region and the piston's
pressure, per snapshot.

Reads a sphdem run of a plate case (an output directory: its snapshots,
case.yaml and <case>_injection_pressure.csv; e.g. inputs/plate_melt_pp.yaml
with `output.fields` naming velocity and frozen) and prints, for every
snapshot (or each --time):

  fill      the resin in the plate (y < 0, --plate) as a fraction of the
            plate's area (sum of spacing^2 rho0 / rho, rho0 the case's
            resin.density: a compressed resin fills less), in the cavity below the
            bath (y < --cavity-top) as a fraction of --cavity-area, and the
            x reached by the resin in the plate (left and right fronts)
  profile   at each station x (--stations, mm), the resin within --width/2:
            u_x in --bins equal bins across the gap (--span); "full" when
            every bin holds resin; peak/mean = the largest bin mean over the
            mean of the bins (all resin, the frozen included); peak/mean
            flowing = the same over the bins between the frozen layers (bins
            whose resin is mostly unfrozen); the frozen layers' thickness at
            the top and bottom walls (frozen resin area in the strip over
            its width). Plane Poiseuille flow sampled in the same bins gives
            the "Newtonian" value printed in the header (1.5 continuous), a
            power-law fluid of index n (2n + 1)/(n + 1)
  orientation  a_xx = <p_x^2> of the fibers per region (the regions and the
            wall/core split of tools/paper_seeds.py) with the fiber counts
  pressure  the piston's speed and the resin pressure at its face, from the
            CSV at the snapshot's time (nearest row)

--markdown prints the tables as Markdown; -o PREFIX writes PREFIX_fill.png
(piston pressure and speed, plate fill, peak/mean per station against time)
and PREFIX_profiles.png (u_x across the gap per station at the --time
values, or the last snapshot).

examples:
  tools/melt_report.py out/plate_melt_pp --stations -30 -20 -10 10 20 30
  tools/melt_report.py out/plate_melt_pp --time 0.04 --time 0.08 --markdown -o docs/img/melt_plate
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np, print_table  # noqa: E402
from velocity_profile import bin_profile, strip  # noqa: E402
from paper_seeds import orientation, REGIONS  # noqa: E402

ORIENT_REGIONS = [r for r in REGIONS if r != "bath"]


def poiseuille_bins(bins):
    """peak/mean of plane Poiseuille flow averaged in `bins` equal bins
    across the gap (the value a Newtonian profile gives in this sampling)."""
    s = np.linspace(0.0, 1.0, 200 * bins + 1)
    u = 6 * s * (1 - s)
    means = [np.mean(u[(s >= k / bins) & (s <= (k + 1) / bins)]) for k in range(bins)]
    return max(means) / np.mean(means)


def power_law_ratio(n):
    """peak/mean of a power-law fluid's plane Poiseuille flow."""
    return (2 * n + 1) / (n + 1)


def read_pressure(path, case):
    """(time, speed, pressure) arrays of the first moving wall's rows of
    <case>_injection_pressure.csv in the run directory, or None."""
    name = os.path.join(path, "%s_injection_pressure.csv" % case)
    if not os.path.isfile(name):
        return None
    t, v, p, wall = [], [], [], None
    with open(name) as f:
        for row in csv.DictReader(f):
            wall = wall or row["wall"]
            if row["wall"] != wall:
                continue
            t.append(float(row["time_s"]))
            v.append(float(row["speed_m_per_s"]))
            p.append(float(row["pressure_pa"]))
    return np.array(t), np.array(v), np.array(p)


def station_profile(x, u, frozen, at, width, bins, span):
    """The profile numbers of one station (dict), see the module doc."""
    y = x[:, 1]
    inside = np.abs(x[:, 0] - at) <= 0.5 * width
    s, uu = strip(x, np.stack([u, np.zeros_like(u)], axis=1), at, width, "y")
    yb, ub, nb = bin_profile(s, uu, bins, span, min_count=1)
    out = dict(bins=len(yb), full=len(yb) == bins, ratio=np.nan, ratio_flowing=np.nan, mean=np.nan,
               peak=np.nan, top=np.nan, bottom=np.nan, yb=yb, ub=ub)
    if len(yb) < 3:
        return out
    out.update(ratio=float(np.max(ub) / np.mean(ub)) if np.mean(ub) > 0 else np.nan, mean=float(np.mean(ub)),
               peak=float(np.max(ub)))
    if frozen is not None:
        f = frozen[inside] > 0.5
        ys = y[inside]
        mid = 0.5 * (span[0] + span[1])
        out["frozen_top_count"] = int(np.count_nonzero(f & (ys > mid)))
        out["frozen_bottom_count"] = int(np.count_nonzero(f & (ys <= mid)))
        # bins mostly unfrozen: the flowing part between the frozen layers
        _, fb, _ = bin_profile(s, f.astype(float), bins, span, min_count=1)
        flowing = fb < 0.5
        if np.count_nonzero(flowing) >= 3 and np.mean(ub[flowing]) > 0:
            out["ratio_flowing"] = float(np.max(ub[flowing]) / np.mean(ub[flowing]))
    return out


def fmt(x, form="%.3f"):
    return form % x if np.isfinite(x) else "-"


def analyse(snap, a, spacing, rho0, pressure):
    """All numbers of one snapshot (dict)."""
    x, v = snap.fluid("velocity")
    frozen = snap.read("fluid/frozen", required=False)
    px0, px1, py0, py1 = (c * MM for c in a.plate)
    in_plate = (x[:, 0] >= px0) & (x[:, 0] <= px1) & (x[:, 1] >= py0) & (x[:, 1] <= py1)
    cell = spacing * spacing
    # Each particle's area m / rho = spacing^2 rho0 / rho (the resin is
    # compressed by the pressure: counting spacing^2 would overfill).
    rho = snap.read("fluid/density", required=False)
    area = cell * (rho0 / rho if rho is not None and rho0 else np.ones(len(x)))
    plate_area = (px1 - px0) * (py1 - py0)
    row = dict(time=snap.time, plate=np.sum(area[in_plate]) / plate_area,
               cavity=np.sum(area[x[:, 1] < a.cavity_top * MM]) / (a.cavity_area * MM * MM),
               left=float(np.min(x[in_plate, 0])) if in_plate.any() else np.nan,
               right=float(np.max(x[in_plate, 0])) if in_plate.any() else np.nan,
               frozen=float(np.mean(frozen > 0.5)) if frozen is not None and len(frozen) else 0.0,
               speed=np.nan, pressure=np.nan)
    if pressure is not None and len(pressure[0]):
        k = int(np.argmin(np.abs(pressure[0] - snap.time)))
        row.update(speed=pressure[1][k], pressure=pressure[2][k])
    span = (a.span[0] * MM, a.span[1] * MM)
    row["stations"] = {}
    for at in a.stations:
        st = station_profile(x, v[:, 0] * (1 if at >= 0 else -1), frozen, at * MM, a.width * MM, a.bins, span)
        for side in ("top", "bottom"):
            if "frozen_%s_count" % side in st:
                st[side] = st["frozen_%s_count" % side] * cell / (a.width * MM)
        row["stations"][at] = st
    fibers = snap.fibers(required=False)
    row["orientation"] = orientation(snap) if fibers is not None and fibers.count else None
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("--stations", nargs="+", type=float, default=[-30.0, -20.0, -10.0, 10.0, 20.0, 30.0],
                    metavar="X", help="profile stations x [mm] (default -30 -20 -10 10 20 30); u_x is taken"
                    " outwards (its sign flipped at x < 0)")
    ap.add_argument("--width", type=float, default=2.0, help="station strip width [mm] (default 2)")
    ap.add_argument("--span", nargs=2, type=float, default=[-4.0, 0.0], metavar=("Y0", "Y1"),
                    help="the gap across the arms [mm] (default -4 0)")
    ap.add_argument("--bins", type=int, default=12, help="bins across the gap (default 12)")
    ap.add_argument("--plate", nargs=4, type=float, default=[-40.0, 40.0, -4.0, 0.0],
                    metavar=("X0", "X1", "Y0", "Y1"), help="the plate [mm] (default -40 40 -4 0)")
    ap.add_argument("--cavity-top", type=float, default=30.0,
                    help="the cavity below the bath: y below this [mm] (default 30)")
    ap.add_argument("--cavity-area", type=float, default=800.0,
                    help="the cavity's area [mm^2] (default 800: nozzle, gate and plate)")
    ap.add_argument("--spacing", help="particle spacing (default: the case's numerics.spacing)")
    ap.add_argument("--markdown", action="store_true", help="print the tables as Markdown")
    ap.add_argument("-o", "--output", metavar="PREFIX", help="write PREFIX_fill.png and PREFIX_profiles.png")
    a = ap.parse_args()
    refs = io.list_snapshots(a.path)
    chosen = io.select(refs, a.time, True if not a.time else False, a.tolerance)
    case = io.read_case(a.path) or {}
    if a.spacing is not None:
        spacing = io.parse_length(a.spacing)
    elif (case.get("numerics") or {}).get("spacing") is not None:
        spacing = float(case["numerics"]["spacing"])
    else:
        raise io.ToolError("no numerics.spacing in the run's case.yaml: give --spacing")
    first = io.Snapshot(chosen[0])
    directory = a.path if os.path.isdir(a.path) else os.path.dirname(os.path.abspath(a.path))
    pressure = read_pressure(directory, first.case)
    rho0 = (case.get("resin") or {}).get("density")
    rho0 = float(rho0) if rho0 is not None else None
    rows = [analyse(io.Snapshot(r), a, spacing, rho0, pressure) for r in chosen]

    print("Fill (resin area m / rho over the region's area; fronts: the plate's resin's extreme x):")
    print_table(["t [s]", "plate", "cavity", "left front [mm]", "right front [mm]", "frozen resin",
                 "piston [m/s]", "piston face [MPa]"],
                [[fmt(r["time"], "%.4f"), fmt(r["plate"]), fmt(r["cavity"]), fmt(r["left"] / MM, "%.1f"),
                  fmt(r["right"] / MM, "%.1f"), fmt(r["frozen"], "%.4f"), fmt(r["speed"]),
                  fmt(r["pressure"] / 1e6, "%.3f")] for r in rows], a.markdown)

    print("Profiles across the arms: peak/mean of all resin, of the flowing part (bins with resin of %d,"
          " mean speed);"
          " Newtonian in these bins %.3f (continuous 1.5), power law n = 0.3: %.3f"
          % (a.bins, poiseuille_bins(a.bins), power_law_ratio(0.3)))
    header = ["t [s]"] + ["x = %g mm" % s for s in a.stations]
    body = []
    for r in rows:
        cells = [fmt(r["time"], "%.4f")]
        for at in a.stations:
            st = r["stations"][at]
            if st["bins"] < 3:
                cells.append("-")
                continue
            cells.append("%s, %s (%d%s, %s m/s)" % (fmt(st["ratio"]), fmt(st["ratio_flowing"]), st["bins"],
                                                    "" if st["full"] else " partial", fmt(st["mean"], "%.2f")))
        body.append(cells)
    print_table(header, body, a.markdown)

    print("Frozen layers at the stations, top / bottom wall [mm] (frozen resin area in the strip / width):")
    body = []
    for r in rows:
        body.append([fmt(r["time"], "%.4f")] + ["%s / %s" % (fmt(r["stations"][at]["top"] / MM),
                                                             fmt(r["stations"][at]["bottom"] / MM))
                                                for at in a.stations])
    print_table(header, body, a.markdown)

    orient = [r for r in rows if r["orientation"] is not None]
    if orient:
        print("Orientation a_xx (fibers) per region (tools/paper_seeds.py's regions):")
        print_table(["t [s]"] + ORIENT_REGIONS,
                    [[fmt(r["time"], "%.4f")] + ["%s (%d)" % (fmt(r["orientation"][k][1], "%.2f"),
                                                              r["orientation"][k][0]) for k in ORIENT_REGIONS]
                     for r in orient], a.markdown)
    if pressure is not None and len(pressure[0]):
        k = int(np.argmax(pressure[2]))
        print("Piston: largest face pressure %.3f MPa at t = %.4f s (speed %.3f m/s); at the end (t = %.4f s)"
              " %.3f MPa, %.3f m/s" % (pressure[2][k] / 1e6, pressure[0][k], pressure[1][k], pressure[0][-1],
                                      pressure[2][-1] / 1e6, pressure[1][-1]))

    if not a.output:
        return
    plt = io.pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    t = np.array([r["time"] for r in rows])
    ax = axes[0]
    if pressure is not None and len(pressure[0]):
        ax.plot(pressure[0], pressure[2] / 1e6, "C3-", label="face pressure [MPa]")
        ax2 = ax.twinx()
        ax2.plot(pressure[0], pressure[1], "C0--", label="piston speed [m/s]")
        ax2.set_ylabel("piston speed [m/s]", color="C0")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("resin pressure at the piston [MPa]", color="C3")
    ax.set_title("the piston (injection pressure)", fontsize=10)
    ax.grid(alpha=0.3)
    ax = axes[1]
    ax.plot(t, [r["plate"] for r in rows], "o-", ms=3, label="plate")
    ax.plot(t, [r["cavity"] for r in rows], "s-", ms=3, label="cavity (nozzle, gate, plate)")
    ax.plot(t, [r["frozen"] for r in rows], "^-", ms=3, label="frozen resin (of all)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("fraction filled")
    ax.set_title("fill", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[2]
    for j, at in enumerate(a.stations):
        pts = [(r["time"], r["stations"][at]["ratio"]) for r in rows if r["stations"][at]["full"]]
        if pts:
            ax.plot(*zip(*pts), "o-", ms=3, color="C%d" % j, label="x = %g mm" % at)
    ax.axhline(poiseuille_bins(a.bins), color="k", ls="--", lw=0.8, label="Newtonian (Poiseuille), same bins")
    ax.axhline(power_law_ratio(0.3), color="0.5", ls=":", lw=0.8, label="power law n = 0.3")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("peak/mean of u_x across the gap")
    ax.set_title("arm profiles (stations full across the gap)", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.suptitle(first.case, fontsize=10)
    fig.tight_layout()
    fig.savefig(a.output + "_fill.png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    print(a.output + "_fill.png")

    shown = rows if a.time else rows[-1:]
    fig, axes = plt.subplots(1, len(a.stations), figsize=(2.6 * len(a.stations), 3.4), squeeze=False, sharey=True)
    for j, at in enumerate(a.stations):
        ax = axes[0][j]
        for i, r in enumerate(shown):
            st = r["stations"][at]
            if st["bins"] >= 3:
                ax.plot(st["ub"], st["yb"] / MM, "o-", ms=3, color="C%d" % i, label="t = %.3f s" % r["time"])
        ax.set_title("x = %g mm" % at, fontsize=9)
        ax.set_xlabel("u_x outwards [m/s]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("y [mm]")
    busiest = max(range(len(a.stations)), key=lambda j: len(axes[0][j].get_lines()))
    axes[0][busiest].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.output + "_profiles.png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    print(a.output + "_profiles.png")


if __name__ == "__main__":
    io.run(main)
