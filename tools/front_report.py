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

Is the front a fountain (docs/validation.md section 17)?
- --channel Y0,Y1 (mm): the plate's two walls; per snapshot and per arm
  (x beyond the gate, --gate half-width), the front's tip (the resin's
  largest |x| in the plate), its wall contacts (the largest |x| of the resin
  within one spacing of each wall) and the tip's lead over their mean, in
  spacings and over the semicircle's lead for particle centres, (W - dp)/2.
  A fountain front leads by about 0.8-1 of it; a plug gliding on the walls
  by much more; a wall jet has no contact on one wall.
- --tracers T:X0,X1,Y0,Y1 (mm; repeatable): the resin particles in that box
  at the snapshot nearest T, followed by id through the later snapshots:
  how many lie on a wall (a wall particle within 1.5 spacings: the first
  resin row), their median distance from the walls, and how far behind the
  arm's tip they are. In a fountain the core particles behind the front run
  to it, turn and are laid on the walls; in a plug they stay in the core.
  --tracer-png draws their paths, coloured by time.

Do two fronts meet behind an insert (a core the stream splits around)?
- --insert X0,X1,Y0,Y1 (mm): the insert's box, the flow along +x. Per
  snapshot, each stream's lead beside it (the largest x of the resin above
  Y1 and below Y0), the resin's lead in its shadow (Y0 < y < Y1, x > X1)
  and the empty area there between the insert's back face and that lead
  (cells dp/2 wide with no resin within a spacing: the air the streams
  close in against the insert, which the trapped-air list leaves out as
  air against a wall); the weld rows sorted into the wake (the shadow),
  upstream (x < X0), beside the insert and downstream outside the shadow,
  with the first wake rows against the time both streams passed the insert.

examples:
  tools/front_report.py out/plate
  tools/front_report.py out/plate --spacing 3e-4 --csv gap.csv --png docs/img/plate_front_events.png
  tools/front_report.py out/plate_melt_front --spacing 6e-4 --channel=-4,0 \\
      --tracers 0.05:9,13,-2.6,-1.4 --tracer-png tracers.png
  tools/front_report.py out/insert_melt_front --spacing 6e-4 --insert=19,25,-2,2
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


def parse_floats(text, n, what):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != n:
        raise io.ToolError("bad %s '%s': want %d numbers separated by commas" % (what, text, n))
    return values


def arm_front(x, y0, y1, dp, gate, side):
    """(tip, contact at y0, contact at y1) [m] of one arm (side +1: x > gate,
    -1: x < -gate) as distances |x| from the centre; None without resin
    there. A contact is None when no resin touches that wall."""
    inside = (x[:, 1] > y0) & (x[:, 1] < y1) & (side * x[:, 0] > gate)
    if not np.any(inside):
        return None
    d = side * x[inside, 0]
    y = x[inside, 1]
    low, high = d[y < y0 + dp], d[y > y1 - dp]
    return (float(d.max()), float(low.max()) if len(low) else None,
            float(high.max()) if len(high) else None)


def channel_rows(snaps, y0, y1, dp, gate):
    """Per snapshot and arm: (time, side, tip, contact0, contact1, lead in dp, lead /
    the semicircle's), lead None without both contacts."""
    rows, half = [], (y1 - y0 - dp) / 2
    for s in snaps:
        x = s.read("fluid/position")
        for side in (1, -1):
            f = arm_front(x, y0, y1, dp, gate, side)
            if f is None:
                continue
            tip, c0, c1 = f
            lead = tip - 0.5 * (c0 + c1) if c0 is not None and c1 is not None else None
            rows.append((s.time, side, tip, c0, c1, None if lead is None else lead / dp,
                         None if lead is None else lead / half))
    return rows


def track(snaps, t0, box):
    """The resin particles in box (x0, x1, y0, y1) [m] at the snapshot nearest
    t0, through that and the later snapshots: [(time, ids, positions,
    distance to the nearest wall particle)]."""
    from scipy.spatial import cKDTree
    start = min(range(len(snaps)), key=lambda k: abs(snaps[k].time - t0))
    x = snaps[start].read("fluid/position")
    ids = snaps[start].read("fluid/id")
    chosen = ids[(x[:, 0] >= box[0]) & (x[:, 0] <= box[1]) & (x[:, 1] >= box[2]) & (x[:, 1] <= box[3])]
    if len(chosen) == 0:
        raise io.ToolError("no resin in %s at t = %g s" % (fmt_box(box), snaps[start].time))
    out = []
    for s in snaps[start:]:
        sid, sx = s.read("fluid/id"), s.read("fluid/position")
        row = dict(zip(sid.tolist(), range(len(sid))))
        keep = [i for i in chosen.tolist() if i in row]
        p = sx[[row[i] for i in keep]]
        walls = s.walls()
        dist = cKDTree(walls).query(p)[0] if walls is not None and len(walls) else np.full(len(p), np.inf)
        out.append((s.time, np.array(keep), p, dist))
    return out


def insert_rows(snaps, box, dp):
    """Per snapshot, the streams around the insert box (x0, x1, y0, y1) [m]:
    (time, upper stream's lead x, lower's, lead x in the shadow, empty area
    [m^2] in the shadow between x1 and that lead); a lead None without resin."""
    x0, x1, y0, y1 = box
    cell = 0.5 * dp
    rows = []
    for s in snaps:
        x = s.read("fluid/position")
        lead = lambda m: float(x[m, 0].max()) if np.any(m) else None
        upper, lower = lead(x[:, 1] > y1), lead(x[:, 1] < y0)
        shadow = (x[:, 0] > x1) & (x[:, 1] > y0) & (x[:, 1] < y1)
        wake = lead(shadow)
        empty = 0.0
        if wake is not None:
            cx = np.arange(x1 + 0.5 * cell, wake, cell)
            cy = np.arange(y0 + 0.5 * cell, y1, cell)
            if len(cx) and len(cy):
                from scipy.spatial import cKDTree
                g = np.stack(np.meshgrid(cx, cy), axis=-1).reshape(-1, 2)
                near = cKDTree(x).query(g, distance_upper_bound=dp * (1 + 1e-9))[0]
                empty = float(np.sum(~np.isfinite(near))) * cell * cell
        rows.append((s.time, upper, lower, wake, empty))
    return rows


def sort_welds(events, box):
    """The weld rows by place: {'wake': [...], 'upstream', 'beside', 'downstream'}."""
    x0, x1, y0, y1 = box
    out = {"wake": [], "upstream": [], "beside": [], "downstream": []}
    for e in events:
        if e["kind"] != "weld_line":
            continue
        x, y = float(e["x_m"]), float(e["y_m"])
        place = ("upstream" if x < x0 else "beside" if x <= x1
                 else "wake" if y0 < y < y1 else "downstream")
        out[place].append(e)
    return out


def fmt_box(box):
    return "x [%g, %g] mm, y [%g, %g] mm" % tuple(v / MM for v in box)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory", help="a run's output directory")
    ap.add_argument("--spacing", type=float, default=3e-4, help="particle spacing dp [m] (default 3e-4)")
    ap.add_argument("--csv", help="write time_s, piston_travel_m, gap_m, gap_spacings per snapshot")
    ap.add_argument("--png", help="figure: the gap against time and the events over the mold")
    ap.add_argument("--channel", metavar="Y0,Y1", help="the plate's walls [mm]: the arms' front shape")
    ap.add_argument("--gate", type=float, default=3.0, help="the gate's half-width [mm] (default 3)")
    ap.add_argument("--tracers", action="append", default=[], metavar="T:X0,X1,Y0,Y1",
                    help="follow the resin in this box [mm] at time T [s] (repeatable)")
    ap.add_argument("--tracer-png", help="figure: the tracers' paths over the last snapshot's mold")
    ap.add_argument("--insert", metavar="X0,X1,Y0,Y1",
                    help="an insert's box [mm], flow along +x: the streams around it and the weld line behind it")
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
    if a.channel:
        y0, y1 = (v * MM for v in parse_floats(a.channel, 2, "--channel"))
        print("arms' fronts (tip and wall contacts as |x| [mm]; lead over the semicircle's (W - dp)/2):")
        for t, side, tip, c0, c1, lead, ratio in channel_rows(snaps, y0, y1, a.spacing, a.gate * MM):
            c = lambda v: "  none" if v is None else "%6.2f" % (v / MM)
            print("  t = %.4f s  %s arm  tip %6.2f  contacts %s %s  lead %s" % (
                t, "right" if side > 0 else "left ", tip / MM, c(c0), c(c1),
                "(a wall not reached)" if lead is None else "%5.2f dp = %.2f" % (lead, ratio)))
    if a.insert:
        box = [v * MM for v in parse_floats(a.insert, 4, "--insert")]
        print("streams around the insert %s (leads as x [mm]; air: empty area in its shadow [mm^2]):"
              % fmt_box(box))
        passed = None
        for t, upper, lower, wake, empty in insert_rows(snaps, box, a.spacing):
            c = lambda v: "  none" if v is None else "%6.2f" % (v / MM)
            print("  t = %.4f s  upper %s  lower %s  shadow %s  air %6.2f" % (
                t, c(upper), c(lower), c(wake), empty / MM ** 2))
            if passed is None and upper is not None and lower is not None and min(upper, lower) > box[1]:
                passed = t
        print("both streams past the insert's back face (x = %g mm) at %s" % (
            box[1] / MM, "no snapshot" if passed is None else "t = %.4f s" % passed))
        if events is not None:
            welds = sort_welds(events, box)
            print("weld_line rows: %s" % ", ".join("%d %s" % (len(v), k) for k, v in welds.items()))
            for e in sorted(welds["wake"], key=lambda e: float(e["time_s"]))[:5]:
                print("  wake: t = %.4f s at (%.2f, %.2f) mm" % (
                    float(e["time_s"]), float(e["x_m"]) / MM, float(e["y_m"]) / MM))
            if welds["wake"]:
                xs = [float(e["x_m"]) / MM for e in welds["wake"]]
                ys = [float(e["y_m"]) / MM for e in welds["wake"]]
                ts = [float(e["time_s"]) for e in welds["wake"]]
                print("  wake rows span x %.2f-%.2f mm, y %.2f-%.2f mm, t %.4f-%.4f s" % (
                    min(xs), max(xs), min(ys), max(ys), min(ts), max(ts)))
            air = [e for e in events if e["kind"] == "trapped_air"]
            shadow = [e for e in air if float(e["x_m"]) > box[1] and box[2] < float(e["y_m"]) < box[3]]
            print("trapped_air rows: %d in the shadow, %d elsewhere" % (len(shadow), len(air) - len(shadow)))
            for e in shadow:
                print("  shadow: t = %.4f s at (%.2f, %.2f) mm, %.3g mm^2" % (
                    float(e["time_s"]), float(e["x_m"]) / MM, float(e["y_m"]) / MM, float(e["size"]) / MM ** 2))
    tracks = []
    for spec in a.tracers:
        t0, sep, rest = spec.partition(":")
        try:
            t0 = float(t0)
        except ValueError:
            sep = ""
        if not sep:
            raise io.ToolError("bad --tracers '%s': want T:X0,X1,Y0,Y1 (T in s, lengths in mm)" % spec)
        box = [v * MM for v in parse_floats(rest, 4, "--tracers box")]
        tr = track(snaps, t0, box)
        tracks.append(tr)
        print("tracers: %d resin particles in %s at t = %.4f s (on a wall: within 1.5 dp of a wall particle)"
              % (len(tr[0][1]), fmt_box(box), tr[0][0]))
        side = 1 if box[0] + box[1] >= 0 else -1
        tips = {}
        if a.channel:  # the arm's tip at each time, to say how far behind it the tracers are
            tips = {r[0]: r[2] for r in channel_rows(snaps, y0, y1, a.spacing, a.gate * MM) if r[1] == side}
        for t, ids, p, dist in tr:
            on = dist < 1.5 * a.spacing
            behind = ""
            if t in tips and np.any(on):
                behind = "  on-wall ones %.1f-%.1f dp behind the tip" % (
                    float(np.min(tips[t] - side * p[on, 0])) / a.spacing,
                    float(np.max(tips[t] - side * p[on, 0])) / a.spacing)
            print("  t = %.4f s  on a wall %3d of %3d  median wall distance %5.2f dp  mean |x| %6.2f mm%s"
                  % (t, int(np.sum(on)), len(ids), float(np.median(dist)) / a.spacing,
                     float(np.mean(np.abs(p[:, 0]))) / MM, behind))
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
    if a.tracer_png and tracks:
        plt = io.pyplot()
        fig, ax = plt.subplots(figsize=(10, 4))
        io.draw_mold(ax, snaps[-1])
        x = snaps[-1].read("fluid/position")
        ax.scatter(x[:, 0] / MM, x[:, 1] / MM, s=1, c="0.85", linewidths=0, rasterized=True)
        every = np.vstack([p for tr in tracks for (_, _, p, _) in tr])
        for tr in tracks:
            t = np.concatenate([np.full(len(p), time * 1e3) for (time, _, p, _) in tr])
            p = np.vstack([p for (_, _, p, _) in tr])
            sc = ax.scatter(p[:, 0] / MM, p[:, 1] / MM, c=t, s=5, cmap="viridis", linewidths=0)
        fig.colorbar(sc, ax=ax, label="t [ms]")
        margin = 2.0
        ax.set_xlim(every[:, 0].min() / MM - margin, every[:, 0].max() / MM + margin)
        ax.set_ylim(every[:, 1].min() / MM - margin, every[:, 1].max() / MM + margin)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title("tracers, coloured by time (grey: the resin at t = %.4g s)" % snaps[-1].time, fontsize=10)
        fig.tight_layout()
        fig.savefig(a.tracer_png, dpi=130)
        print("wrote %s" % a.tracer_png)


if __name__ == "__main__":
    io.run(main)
