#!/usr/bin/python3
"""The paper comparison over several fiber placements: orientation, bond
stress, breakage and cost of the runs tools/paper_seeds.sh writes, per run
and per case with the spread between seeds (docs/paper-comparison.md,
"Seeds: torque and glass").

Reads OUT/{e1e8,glass,breakage}_sSEED/ (sphdem output directories), their
logs OUT/NAME.log ("done:" line) and OUT/NAME.time (/usr/bin/time -v). For
each run, at the last snapshot (or --time T, --common, below):

  orientation   a_xx = <p_x^2> of the fibers' end-to-end unit vectors whose
                centroid is in a region (plate runs): the arms' near-wall
                layers (within 1 mm of y = 0 or y = -4 mm, |x| > 3 mm), the
                arms' core (-3 < y < -1 mm), the nozzle's near-wall strips
                (within 1 mm of its slanted walls, 5 < y < 30 mm) and its
                core (the middle half of its width), the gate (|x| < 3 mm,
                0 < y < 5 mm), the bath (y > 30 mm, where the fibers start
                along x), its near-wall strips (|x| > 14 mm: within 1 mm of
                its side walls) and its core (|x| < 7.5 mm); 1 = along x,
                0 = along y (the injection); along the nozzle's walls
                a_xx = cos^2(64.4 deg) = 0.19
  bond stress   the largest run peak over all bonds (bond_tensile_stress_max,
                recorded at every DEM sub-step, docs/dem.md "Bond stress
                peaks"), the output interval it falls in and where that bond
                is then, the largest peak after the start-up (the intervals
                after the first, or after --after T: the fibers start at
                rest in a resin moving at the piston's speed), the largest
                shear peak, the broken bonds
  lengths       fibers (pieces), L_N and L_W (breakage runs)
  cost          SPH steps, user + system CPU and wall time of the whole job
                (NaN while a run is still going)

--common analyses all plate runs at the latest snapshot time every one of
them has reached (the breakage runs likewise), so that runs still going, or
stopped by paper_seeds.sh --timeout, compare at one time; --time T picks
the plate runs' snapshot nearest T instead. In 2D a_yy = 1 - a_xx.

and per case: mean +- sd and min..max over the seeds; the glass/E = 1e8 CPU
ratio per seed (both plates of a seed run one after the other).
--markdown prints the tables as Markdown; -o PREFIX writes PREFIX_bonds.png
(the largest bond tensile stress of each output interval, plotted at its
end, every run),
PREFIX_orientation.png (a_xx per region, every seed) and, with breakage
runs, PREFIX_lengths.png (L_N, L_W against time).

examples:
  tools/paper_seeds.py out/paper_seeds
  tools/paper_seeds.py out/paper_seeds --markdown -o docs/img/paper_seeds
  tools/paper_seeds.py out/paper_seeds --common
  tools/paper_seeds.py out/paper_seeds --time 0.06
"""
import argparse
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np, print_table  # noqa: E402
from fiber_lengths import averages, piece_lengths  # noqa: E402

MPA = 1e6
CASES = ("e1e8", "glass", "breakage")
TITLES = {"e1e8": "3.8 % plate, E = 1e8 Pa", "glass": "3.8 % plate, glass (72 GPa, implicit bonds)",
          "breakage": "breakage case (aspect ratio 20, E = 1e8, 0.2 MPa)"}
REGIONS = ("arm_wall", "arm_core", "nozzle_wall", "nozzle_core", "gate", "bath_wall", "bath_core", "bath")


def nozzle_half_width(y):
    """Half width [m] of the plate cases' nozzle at height y: 3 mm at y = 5 mm
    to 15 mm at y = 30 mm (inputs/plate_fibers_3.8.yaml)."""
    return 3 * MM + (y - 5 * MM) * (12.0 / 25.0)


def region_masks(c):
    """Boolean masks of the fiber centroids c (n, 2) [m] per region."""
    x, y = np.abs(c[:, 0]), c[:, 1]
    arm = (x > 3 * MM) & (y <= 0) & (y >= -4 * MM)
    in_nozzle = (y > 5 * MM) & (y < 30 * MM)
    w = nozzle_half_width(y)
    return {"arm_wall": arm & ((y > -1 * MM) | (y < -3 * MM)),
            "arm_core": arm & (y >= -3 * MM) & (y <= -1 * MM),
            "nozzle_wall": in_nozzle & (x > w - 1 * MM) & (x <= w),
            "nozzle_core": in_nozzle & (x < 0.5 * w),
            "gate": (x < 3 * MM) & (y >= 0) & (y <= 5 * MM),
            "bath_wall": (y >= 30 * MM) & (x > 14 * MM),
            "bath_core": (y >= 30 * MM) & (x < 7.5 * MM),
            "bath": y >= 30 * MM}


def orientation(snap):
    """{region: (N, a_xx)} of a snapshot's fibers."""
    f = snap.fibers()
    c, p = f.centroids(), f.directions()
    ok = np.all(np.isfinite(p), axis=1)
    c, p = c[ok], p[ok]
    out = {}
    for name, m in region_masks(c).items():
        n = int(np.count_nonzero(m))
        out[name] = (n, float(np.mean(p[m, 0] ** 2)) if n else np.nan)
    return out


def bond_peaks(snap):
    """(run peak of sigma [Pa], its bond row, run peak of tau [Pa], interval
    peak of sigma [Pa], broken bonds) of a snapshot; NaN without bonds."""
    sig = snap.read("dem/lines/bond_tensile_stress_max", required=False)
    if sig is None or len(sig) == 0:
        return np.nan, -1, np.nan, np.nan, 0
    tau = snap.read("dem/lines/bond_shear_stress_max")
    itv = snap.read("dem/lines/bond_tensile_stress_interval_max")
    broken = snap.read("dem/lines/broken") > 0.5
    k = int(np.argmax(sig))
    return float(sig[k]), k, float(np.max(tau)), float(np.max(itv)), int(np.count_nonzero(broken))


def read_cost(out, name):
    """{steps, t_end, user, sys, wall} from NAME.log and NAME.time (NaN if absent)."""
    cost = dict(steps=np.nan, t_end=np.nan, user=np.nan, sys=np.nan, wall=np.nan)
    log = os.path.join(out, name + ".log")
    if os.path.isfile(log):
        m = re.search(r"^done: (\d+) steps to t = ([0-9.eE+-]+) s", open(log).read(), re.M)
        if m:
            cost["steps"], cost["t_end"] = int(m.group(1)), float(m.group(2))
    tim = os.path.join(out, name + ".time")
    if os.path.isfile(tim):
        text = open(tim).read()
        for key, pat in (("user", r"User time \(seconds\): ([0-9.]+)"),
                         ("sys", r"System time \(seconds\): ([0-9.]+)")):
            m = re.search(pat, text)
            if m:
                cost[key] = float(m.group(1))
        m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([0-9:.]+)", text)
        if m:
            parts = [float(v) for v in m.group(1).split(":")]
            cost["wall"] = sum(v * 60 ** (len(parts) - 1 - i) for i, v in enumerate(parts))
    return cost


def analyse_run(out, case, seed, want_time, after):
    name = "%s_s%s" % (case, seed)
    refs = io.list_snapshots(os.path.join(out, name))
    last = io.select(refs, [want_time] if want_time is not None else None)[0]
    snap = io.Snapshot(last)
    run = dict(case=case, seed=seed, name=name, time=snap.time, cost=read_cost(out, name))
    sig, k, tau, _, broken = bond_peaks(snap)
    run.update(sigma_max=sig, tau_max=tau, broken=broken, bonds=len(snap.read("dem/lines/broken")))
    # The interval holding the peak, and where its bond is at that snapshot.
    series, peak_t, peak_xy = [], np.nan, (np.nan, np.nan)
    for r in refs:
        if r.time > snap.time + 1e-12:
            break
        s = io.Snapshot(r)
        if not s.has("dem/lines/bond_tensile_stress_max"):
            continue
        srun, _, _, sitv, sbroken = bond_peaks(s)
        row = dict(t=s.time, run=srun, interval=sitv, broken=sbroken)
        if case == "breakage":
            got = piece_lengths(s)
            if got is not None:
                ln, lw = averages(got[0])
                row.update(fibers=len(got[0]), L_N=ln, L_W=lw)
        series.append(row)
        if np.isnan(peak_t) and np.isfinite(sig) and srun >= sig * (1 - 1e-12):
            peak_t = s.time
            nodes = s.read("dem/lines/nodes").astype(np.int64)[k]
            peak_xy = tuple(s.read("dem/position")[nodes].mean(axis=0))
    # The peak after the start-up: the intervals that end after `after`
    # (default: all but the first).
    times = [x["t"] for x in series if x["t"] > 0]
    cut = after if after is not None else (times[0] if times else np.inf)
    late = [x["interval"] for x in series if x["t"] > cut * (1 + 1e-9) and np.isfinite(x["interval"])]
    run.update(series=series, peak_time=peak_t, peak_xy=peak_xy, sigma_late=max(late) if late else np.nan)
    if case != "breakage":
        run["orientation"] = orientation(snap)
    else:
        lengths, _ = piece_lengths(snap)
        ln, lw = averages(lengths)
        run.update(fibers=len(lengths), L_N=ln, L_W=lw)
    return run


def common_times(out, found):
    """{case: t}: the latest snapshot time that every plate run (E = 1e8 and
    glass together, so that they compare at one time) and every breakage
    run has reached."""
    last = {}
    for case, seed in found:
        group = "breakage" if case == "breakage" else "plate"
        t = io.list_snapshots(os.path.join(out, "%s_s%s" % (case, seed)))[-1].time
        last[group] = min(last.get(group, np.inf), t)
    return {case: last.get("breakage" if case == "breakage" else "plate") for case in CASES}


def spread(values, form="%.3g"):
    """'mean +- sd (min..max)' of the finite values, or '-'."""
    v = np.array([x for x in values if np.isfinite(x)], float)
    if len(v) == 0:
        return "-"
    fmt = lambda x: form % x  # noqa: E731
    if len(v) == 1:
        return fmt(v[0])
    return "%s +- %s (%s..%s)" % (fmt(v.mean()), fmt(v.std(ddof=1)), fmt(v.min()), fmt(v.max()))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="the directory tools/paper_seeds.sh wrote (--out)")
    ap.add_argument("--time", type=float, metavar="T",
                    help="analyse the snapshot nearest T [s] of every plate run (default: each run's last; the"
                         " breakage runs: their last, or with --common their common time)")
    ap.add_argument("--common", action="store_true",
                    help="analyse the plate runs at the latest snapshot time all of them have reached, and the"
                         " breakage runs likewise (runs still going or stopped by --timeout)")
    ap.add_argument("--after", type=float, metavar="T",
                    help="the 'after start-up' peak: the output intervals that end after T [s] (default: all"
                         " but the first interval)")
    ap.add_argument("--markdown", action="store_true", help="print the tables as Markdown")
    ap.add_argument("-o", "--output", metavar="PREFIX", help="write PREFIX_bonds.png, PREFIX_orientation.png"
                    " and (with breakage runs) PREFIX_lengths.png")
    a = ap.parse_args()
    if not os.path.isdir(a.out):
        raise io.ToolError("%s: no such directory" % a.out)

    found = []
    for case in CASES:
        dirs = glob.glob(os.path.join(a.out, case + "_s*"))
        seeds = sorted((d.rsplit("_s", 1)[1] for d in dirs if os.path.isdir(d)), key=lambda s: (len(s), s))
        found += [(case, seed) for seed in seeds]
    want = common_times(a.out, found) if a.common else {case: None for case in CASES}
    if a.time is not None:
        want.update(e1e8=a.time, glass=a.time)
    runs = [analyse_run(a.out, case, seed, want[case], a.after) for case, seed in found]
    if not runs:
        raise io.ToolError("no runs (e1e8_sN, glass_sN, breakage_sN directories) in %s" % a.out)
    by_case = {c: [r for r in runs if r["case"] == c] for c in CASES}
    g = lambda x: "%.3g" % x if np.isfinite(x) else "-"  # noqa: E731
    a2 = lambda x: "%.2f" % x if np.isfinite(x) else "-"  # noqa: E731

    print("Per run (the snapshot at the time shown; sigma, tau: the run's peaks over every DEM sub-step):")
    rows = []
    for r in runs:
        c = r["cost"]
        rows.append([r["name"], "%.4g" % r["time"], "%d" % c["steps"] if np.isfinite(c["steps"]) else "-",
                     g(c["user"] + c["sys"]), g(c["wall"]), g(r["sigma_max"] / MPA), g(r["sigma_late"] / MPA),
                     g(r["peak_time"] * 1e3), "(%s, %s)" % (g(r["peak_xy"][0] / MM), g(r["peak_xy"][1] / MM)),
                     g(r["tau_max"] / MPA), "%d / %d" % (r["broken"], r["bonds"])])
    print_table(["run", "t [s]", "steps", "CPU [s]", "wall [s]", "max sigma [MPa]", "after start-up",
                 "peak by [ms]",
                 "peak at (x, y) [mm]", "max tau [MPa]", "broken / bonds"], rows, a.markdown)

    plate = [r for r in runs if r["case"] != "breakage"]
    if plate:
        print("Orientation a_xx (N fibers) per region, per run:")
        rows = [[r["name"]] + ["%s (%d)" % (a2(r["orientation"][k][1]), r["orientation"][k][0]) for k in REGIONS]
                for r in plate]
        print_table(["run"] + list(REGIONS), rows, a.markdown)

    print("Per case over the seeds: mean +- sd (min..max):")
    rows = []
    for case, rs in by_case.items():
        if not rs:
            continue
        row = [TITLES[case], "%d" % len(rs), spread([r["sigma_max"] / MPA for r in rs]),
               spread([r["sigma_late"] / MPA for r in rs]),
               spread([r["broken"] for r in rs])]
        if case == "breakage":
            row += [spread([r["fibers"] for r in rs]), spread([r["L_N"] / MM for r in rs]),
                    spread([r["L_W"] / MM for r in rs])]
        else:
            row += ["-", "-", "-"]
        rows.append(row)
    print_table(["case", "seeds", "max sigma [MPa]", "after start-up", "broken bonds", "fibers (pieces)", "L_N [mm]",
                 "L_W [mm]"], rows, a.markdown)
    if plate:
        rows = []
        for case in ("e1e8", "glass"):
            rs = by_case[case]
            if rs:
                rows.append([TITLES[case]] + [spread([r["orientation"][k][1] for r in rs], "%.2f") for k in REGIONS])
        print("Orientation a_xx per case over the seeds: mean +- sd (min..max):")
        print_table(["case"] + list(REGIONS), rows, a.markdown)

    pairs = []
    for r in by_case["glass"]:
        e = [x for x in by_case["e1e8"] if x["seed"] == r["seed"]]
        if e and e[0]["time"] == r["time"]:
            ce, cg = e[0]["cost"], r["cost"]
            if not all(np.isfinite([ce["user"], cg["user"], ce["wall"], cg["wall"]])):
                continue
            pairs.append((r["seed"], (cg["user"] + cg["sys"]) / (ce["user"] + ce["sys"]), cg["wall"] / ce["wall"],
                          cg["steps"] / ce["steps"]))
    if pairs:
        print("Glass against E = 1e8, the same seed and end time (user + system CPU of the whole job):")
        rows = [["seed %s" % s, "%.2f" % u, "%.2f" % w, "%.3f" % n] for s, u, w, n in pairs]
        rows.append(["all", spread([p[1] for p in pairs]), spread([p[2] for p in pairs]),
                     spread([p[3] for p in pairs])])
        print_table(["pair", "CPU ratio", "wall ratio", "steps ratio"], rows, a.markdown)

    if not a.output:
        return
    plt = io.pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    styles = {"e1e8": "C0", "glass": "C3", "breakage": "C2"}
    for r in runs:
        s = [x for x in r["series"] if np.isfinite(x["interval"]) and x["t"] > 0]
        if s:
            ax.plot([x["t"] * 1e3 for x in s], [x["interval"] / MPA for x in s], "o-", ms=3,
                    color=styles[r["case"]], alpha=0.8, label="%s, seed %s" % (r["case"], r["seed"]))
    ax.axhline(936.51, color="k", ls="--", lw=0.8, label="paper: 936.51 MPa (at 0.2 s)")
    ax.set_yscale("log")
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("largest bond tensile stress in the interval [MPa]")
    ax.set_title("bond tensile stress peaks per output interval (every DEM sub-step), at its end",
                 fontsize=10)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3, which="both")
    fig.savefig(a.output + "_bonds.png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(a.output + "_bonds.png")

    if plate:
        fig, ax = plt.subplots(figsize=(9, 4))
        for i, case in enumerate(("e1e8", "glass")):
            for j, r in enumerate(by_case[case]):
                xs = np.arange(len(REGIONS)) + (i - 0.5) * 0.3 + (j - 1) * 0.06
                ys = [r["orientation"][k][1] for k in REGIONS]
                ax.plot(xs, ys, "o" if case == "e1e8" else "s", color=styles[case],
                        label=TITLES[case] if j == 0 else None)
        ax.set_xticks(np.arange(len(REGIONS)))
        ax.set_xticklabels(REGIONS, rotation=20)
        ax.axhline(0.5, color="0.5", ls=":", lw=0.8)
        ax.set_ylim(-0.02, 1.02)
        ax.set_ylabel("a_xx (1: along x, 0: along y)")
        ax.set_title("orientation per region at t = %.4g s, one point per seed" % plate[0]["time"], fontsize=10)
        ax.legend(fontsize=8)
        fig.savefig(a.output + "_orientation.png", dpi=110, bbox_inches="tight")
        plt.close(fig)
        print(a.output + "_orientation.png")

    if by_case["breakage"]:
        fig, ax = plt.subplots(figsize=(7.5, 4))
        for j, r in enumerate(by_case["breakage"]):
            s = [x for x in r["series"] if "L_N" in x]
            t = [x["t"] * 1e3 for x in s]
            ax.plot(t, [x["L_N"] / MM for x in s], "o-", ms=3, color="C%d" % j, label="seed %s: L_N" % r["seed"])
            ax.plot(t, [x["L_W"] / MM for x in s], "s--", ms=3, color="C%d" % j, label="seed %s: L_W" % r["seed"])
        ax.set_xlabel("t [ms]")
        ax.set_ylabel("length [mm]")
        ax.set_title("breakage case: number and weight average fiber length", fontsize=10)
        ax.legend(fontsize=7, ncol=2)
        ax.grid(alpha=0.3)
        fig.savefig(a.output + "_lengths.png", dpi=110, bbox_inches="tight")
        plt.close(fig)
        print(a.output + "_lengths.png")


if __name__ == "__main__":
    io.run(main)
