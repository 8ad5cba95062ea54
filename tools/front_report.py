#!/usr/bin/python3
"""Is the resin on the piston, and where are the weld lines and trapped air?

Reads a sphdem run's output directory (snapshots with the wall set, and the
<case>_front_events.csv that output.front_events writes; docs/physics.md
"Weld lines and trapped air", "Ambient pressure"):

- per snapshot, the gap between the piston and the resin ahead of it: the
  piston is the set of wall particles that moved since the first snapshot,
  its direction of motion u; the gap is the smallest u-distance from the
  piston's leading row to a resin particle within the piston's width, less
  one spacing (0: the resin rests on the piston);
- the front events: weld-line and trapped-air rows, counted per region
  (above y = 0: bath, nozzle and gate; below: the plate or branches), with
  the first ones in the cavity.

Optionally a figure (--png): the gap against time, and the events' positions
over the last snapshot's mold, coloured by time.

examples:
  tools/front_report.py out/plate
  tools/front_report.py out/plate --spacing 3e-4 --csv gap.csv --png docs/img/plate_front_events.png
"""
import argparse
import csv
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402


def piston_gap(first, snap, spacing):
    """(gap [m], piston displacement [m]) of one snapshot, gap None without a piston."""
    ids0, x0 = first.read("wall/id"), first.read("wall/position")
    ids, x = snap.read("wall/id"), snap.read("wall/position")
    start = dict(zip(ids0.tolist(), range(len(ids0))))
    order = np.array([start.get(int(i), -1) for i in ids])
    known = order >= 0
    moved_by = np.zeros_like(x)
    moved_by[known] = x[known] - x0[order[known]]
    moved = np.linalg.norm(moved_by, axis=1) > 1e-9
    if not np.any(moved):
        return None, 0.0
    shift = moved_by[moved].mean(axis=0)
    u = shift / np.linalg.norm(shift)
    piston = x[moved]
    lateral = np.array([-u[1], u[0]])
    side = piston @ lateral
    resin = snap.read("fluid/position")
    ahead = resin[(resin @ lateral >= side.min() - 1e-12) & (resin @ lateral <= side.max() + 1e-12)]
    lead = float(np.max(piston @ u))
    if len(ahead) == 0:
        return float("inf"), float(np.linalg.norm(shift))
    return float(np.min(ahead @ u) - lead - spacing), float(np.linalg.norm(shift))


def read_events(directory):
    names = glob.glob(os.path.join(directory, "*_front_events.csv"))
    if not names:
        return None
    with open(names[0]) as f:
        return [dict(r) for r in csv.DictReader(f)]


def summarise(events):
    lines = []
    for kind in ("weld_line", "trapped_air"):
        rows = [e for e in events if e["kind"] == kind]
        above = [e for e in rows if float(e["y_m"]) >= 0]
        below = sorted((e for e in rows if float(e["y_m"]) < 0), key=lambda e: float(e["time_s"]))
        lines.append("%s: %d rows, %d above y = 0 (bath, nozzle, gate), %d in the cavity below"
                     % (kind, len(rows), len(above), len(below)))
        for e in below[:5]:
            lines.append("  t = %.4f s at (%.1f, %.1f) mm%s" % (
                float(e["time_s"]), float(e["x_m"]) / MM, float(e["y_m"]) / MM,
                ", %.3g mm^2" % (float(e["size"]) / MM ** 2) if kind == "trapped_air" else ""))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory", help="a run's output directory")
    ap.add_argument("--spacing", type=float, default=3e-4, help="particle spacing dp [m] (default 3e-4)")
    ap.add_argument("--csv", help="write time_s, piston_travel_m, gap_m, gap_spacings per snapshot")
    ap.add_argument("--png", help="figure: the gap against time and the events over the mold")
    a = ap.parse_args()
    snaps = [io.Snapshot(r) for r in io.list_snapshots(a.directory)]
    rows = []
    for s in snaps:
        gap, travel = piston_gap(snaps[0], s, a.spacing)
        if gap is not None:
            rows.append((s.time, travel, gap, gap / a.spacing))
    print("piston gap (0: the resin rests on the piston):")
    for t, travel, gap, n in rows:
        print("  t = %.4f s  piston travel %6.2f mm  gap %7.3f mm = %6.2f spacings"
              % (t, travel / MM, gap / MM, n))
    if rows:
        print("largest gap: %.2f spacings" % max(r[3] for r in rows))
    events = read_events(a.directory)
    if events is None:
        print("no *_front_events.csv in %s (output.front_events: true writes it)" % a.directory)
    else:
        print("\n".join(summarise(events)))
    if a.csv:
        io.write_csv(a.csv, ["time_s", "piston_travel_m", "gap_m", "gap_spacings"], rows)
    if a.png:
        plt = io.pyplot()
        fig, (g, m) = plt.subplots(1, 2, figsize=(11, 3.6), gridspec_kw={"width_ratios": [1, 2.2]})
        if rows:
            g.plot([r[0] * 1e3 for r in rows], [r[3] for r in rows], "o-", ms=3)
        g.axhline(2, color="0.5", ls="--", lw=0.8)
        g.set_xlabel("t [ms]")
        g.set_ylabel("piston gap [spacings]")
        io.draw_mold(m, snaps[-1], io.read_case(a.directory))
        if events:
            for kind, marker in (("weld_line", "."), ("trapped_air", "s")):
                e = [r for r in events if r["kind"] == kind]
                if e:
                    sc = m.scatter([float(r["x_m"]) / MM for r in e], [float(r["y_m"]) / MM for r in e],
                                   c=[float(r["time_s"]) * 1e3 for r in e], marker=marker, s=8 if kind == "weld_line" else 14,
                                   cmap="viridis", label=kind.replace("_", " "))
            fig.colorbar(sc, ax=m, label="t [ms]")
            m.legend(loc="upper right", fontsize=8)
        m.set_aspect("equal")
        m.set_xlabel("x [mm]")
        m.set_ylabel("y [mm]")
        fig.tight_layout()
        fig.savefig(a.png, dpi=130)
        print("wrote %s" % a.png)


if __name__ == "__main__":
    io.run(main)
