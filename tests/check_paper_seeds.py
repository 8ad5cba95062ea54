#!/usr/bin/env python3
"""tools/paper_seeds.sh and tools/paper_seeds.py (issue 12 part 7,
docs/paper-comparison.md "Seeds: torque and glass") without real runs:

  - paper_seeds.sh: --help exits 0 and names the options; an unknown option
    or case exits 2 naming it; --skip-existing skips only finished runs
    (a "done:" line in the log); --dry-run prints, per seed, the E = 1e8
    plate, then the glass plate, then the breakage case, each with
    fibers.seed, the end time and the snapshot interval asked for, under
    nice and /usr/bin/time -v, and creates nothing;
  - paper_seeds.py on hand-made snapshots (two seeds of each plate, one
    breakage run, with logs and /usr/bin/time files): the orientation tensor
    per region, the run's bond stress peak with its interval and place, the
    peak after the start-up, the broken bonds, L_N and L_W, the glass/E = 1e8
    CPU and wall ratios, the spread between seeds, all equal to the hand
    values; the PNGs are written; --common analyses runs that ended at
    different times at the latest time all plates reached, --time the
    plates at that time and the breakage runs at their last.

usage: check_paper_seeds.py SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)
src, work = sys.argv[1:3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
script = os.path.join(src, "tools", "paper_seeds.sh")
tool = os.path.join(src, "tools", "paper_seeds.py")
failures = []
MM = 1e-3


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def sh(*args):
    return subprocess.run(["bash", script, *args], capture_output=True, text=True, cwd=work)


# ---- the driver script
r = sh("--help")
expect(r.returncode == 0 and all(o in r.stdout for o in ("--seeds", "--plate-end", "--breakage-end", "--timeout",
                                                         "--ranks", "--dry-run")),
       "--help exits 0 and names the options")
r = sh("--frobnicate")
expect(r.returncode == 2 and "--frobnicate" in r.stderr, "an unknown option exits 2 naming it")
r = sh("--cases", "glass plate")
expect(r.returncode == 2 and "'plate'" in r.stderr, "an unknown case exits 2 naming it")
r = sh("--seeds")
expect(r.returncode == 2 and "--seeds" in r.stderr, "an option without its value exits 2 naming it")
dry_out = os.path.join(work, "dry")
r = sh("--dry-run", "--seeds", "4 7", "--plate-end", "0.02", "--breakage-end", "3e-4", "--breakage-every", "1e-4",
       "--timeout", "900", "--out", dry_out, "--sphdem", "no/such/sphdem")
runs = [ln for ln in r.stdout.splitlines() if " mpirun " in ln]
names = [ln.split()[1].rstrip(":") for ln in runs]
expect(r.returncode == 0 and names == ["e1e8_s4", "glass_s4", "breakage_s4", "e1e8_s7", "glass_s7", "breakage_s7"],
       "--dry-run: per seed the E = 1e8 plate, the glass plate, the breakage case (%s)" % names)
expect(all("nice -n 10 timeout 900 /usr/bin/time -v" in ln and "mpirun -n 2 no/such/sphdem run" in ln
           for ln in runs), "--dry-run: each run under nice, timeout and /usr/bin/time -v on 2 ranks")
expect(all(("fibers.seed=4" in ln) == ("_s4" in ln) for ln in runs), "--dry-run: the seed is passed on")
expect(all("inputs/plate_fibers_3.8.yaml" in ln for ln in runs if "e1e8_" in ln)
       and all("inputs/plate_fibers_glass.yaml" in ln for ln in runs if "glass_" in ln)
       and all("inputs/plate_breakage.yaml" in ln for ln in runs if "breakage_" in ln), "--dry-run: the case files")
expect(all("numerics.end_time=0.02 --set output.every_time=2e-3" in ln for ln in runs if "breakage_" not in ln)
       and all("numerics.end_time=3e-4 --set output.every_time=1e-4" in ln for ln in runs if "breakage_" in ln),
       "--dry-run: end times and snapshot intervals per case")
expect(not os.path.exists(dry_out), "--dry-run creates nothing")

# --skip-existing skips only a run whose log says it finished: /usr/bin/time
# writes NAME.time at the start, so an interrupted run has one too.
skip_out = os.path.join(work, "skip")
os.makedirs(skip_out)
for name, log in (("e1e8_s1", "done: 10 steps to t = 0.12 s\n"), ("glass_s1", "step 10\n")):
    open(os.path.join(skip_out, name + ".time"), "w").close()
    with open(os.path.join(skip_out, name + ".log"), "w") as f:
        f.write(log)
r = sh("--dry-run", "--skip-existing", "--seeds", "1", "--cases", "e1e8 glass", "--out", skip_out,
       "--sphdem", "no/such/sphdem")
expect(r.returncode == 0 and "skip e1e8_s1" in r.stdout and "skip glass_s1" not in r.stdout
       and any("glass_s1:" in ln and " mpirun " in ln for ln in r.stdout.splitlines()),
       "--skip-existing skips the finished run and reruns the interrupted one")


# ---- the analysis on hand-made snapshots
def fiber_block(centre, angle_deg, n=4, d=0.25 * MM):
    """Positions (n, 3) of a straight fiber of n particles."""
    u = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg)), 0.0])
    s = (np.arange(n) - 0.5 * (n - 1)) * d
    return np.asarray(centre + (0.0,), float) * MM + s[:, None] * u


def write_snapshot(path, t, fibers, sigma_max, tau_max, sigma_itv, broken=None, pieces=None):
    """fibers: [(centre_mm, angle_deg)] of 4 particles; bond rows in fiber order."""
    pos = np.vstack([fiber_block(c, a) for c, a in fibers])
    nf = len(fibers)
    fid = np.repeat(np.arange(nf), 4).astype(float)
    nodes = np.array([[4 * f + k, 4 * f + k + 1] for f in range(nf) for k in range(3)], np.int64)
    nb = len(nodes)
    broken = np.zeros(nb) if broken is None else np.asarray(broken, float)
    piece = fid.copy() if pieces is None else np.asarray(pieces[0], float)
    plen = np.full(len(pos), 1.0 * MM) if pieces is None else np.asarray(pieces[1], float)
    with h5py.File(path, "w") as f:
        f.attrs.update(time=t, step=int(t * 1e6), dimension=2, case="hand")
        g = f.create_group("dem")
        g.attrs["count"] = len(pos)
        g["id"], g["position"], g["fiber"] = np.arange(len(pos)), pos, fid
        g["radius"], g["piece"], g["piece_length"] = np.full(len(pos), 0.125 * MM), piece, plen
        lines = g.create_group("lines")
        lines.attrs["count"] = nb
        lines["nodes"], lines["fiber"], lines["broken"] = nodes, np.repeat(np.arange(nf), 3).astype(float), broken
        lines["bond_tensile_stress"] = np.asarray(sigma_itv, float)
        lines["bond_shear_stress"] = np.zeros(nb)
        lines["bond_tensile_stress_max"] = np.asarray(sigma_max, float)
        lines["bond_shear_stress_max"] = np.asarray(tau_max, float)
        lines["bond_tensile_stress_interval_max"] = np.asarray(sigma_itv, float)
        lines["bond_shear_stress_interval_max"] = np.asarray(tau_max, float)


def write_run(out, name, steps, t_end, user, system, wall, snaps):
    d = os.path.join(out, name)
    os.makedirs(d)
    for k, (t, args) in enumerate(snaps):
        write_snapshot(os.path.join(d, "hand_%08d.h5" % k), t, *args)
    with open(os.path.join(out, name + ".log"), "w") as f:
        f.write("step 100 ...\ndone: %d steps to t = %g s in %g s (1e+06 particle-steps/s), %d snapshots in %s\n"
                % (steps, t_end, wall, len(snaps), d))
    m, s = divmod(wall, 60)
    with open(os.path.join(out, name + ".time"), "w") as f:
        f.write("\tCommand being timed: \"mpirun -n 2 sphdem run\"\n\tUser time (seconds): %.2f\n"
                "\tSystem time (seconds): %.2f\n\tElapsed (wall clock) time (h:mm:ss or m:ss): %d:%05.2f\n"
                % (user, system, m, s))


out = os.path.join(work, "runs")
os.makedirs(out)
# Fibers (centres in mm): arm core along x and at 45 degrees (a_xx = 0.75),
# arm wall along y (0), nozzle core along y (0) and nozzle wall at 60
# degrees from x (0.25); gate along x (1); bath core along x (1), bath wall
# strip along y (0): the bath's two give 0.5.
layout = [((-10, -2), 0), ((12, -2), 45), ((20, -0.5), 90), ((0, 20), 90),
          ((-10.1, 20), 60), ((1, 2.5), 0), ((0, 45), 0), ((-14.5, 40), 90)]
hand_axx = dict(arm_wall=0.0, arm_core=0.75, nozzle_wall=0.25, nozzle_core=0.0, gate=1.0, bath_wall=0.0,
                bath_core=1.0, bath=0.5)
nb = 3 * len(layout)


def peaks(value, bond):
    v = np.zeros(nb)
    v[bond] = value
    return v


# E = 1e8 seed 1: the run's peak 2 MPa on bond 4 (fiber 1, the 45-degree one
# at x = 12 mm) is reached in the interval ending at 2 ms; seed 2: 4 MPa at 4 ms.
write_run(out, "e1e8_s1", 1000, 0.004, 10.0, 1.0, 20.5,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.002, (layout, peaks(2e6, 4), peaks(1e5, 4), peaks(2e6, 4))),
           (0.004, (layout, peaks(2e6, 4), peaks(3e5, 4), peaks(1e6, 4)))])
write_run(out, "e1e8_s2", 1000, 0.004, 12.0, 1.0, 26.0,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.004, (layout, peaks(4e6, 7), peaks(1e5, 7), peaks(4e6, 7)))])
# Glass: 8 and 16 MPa; CPU 2 and 3 times seed 1's and 2's.
write_run(out, "glass_s1", 1000, 0.004, 20.0, 2.0, 61.5,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.004, (layout, peaks(8e6, 0), peaks(1e5, 0), peaks(8e6, 0)))])
write_run(out, "glass_s2", 1000, 0.004, 36.0, 3.0, 52.0,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.004, (layout, peaks(16e6, 0), peaks(1e5, 0), peaks(16e6, 0)))])
# Breakage: 3 fibers of 4 particles, one broken bond in fiber 0 splits it
# into pieces of 2 particles (0.5 mm) each: lengths 0.5, 0.5, 1, 1 mm:
# L_N = 0.75 mm, L_W = (0.25 + 0.25 + 1 + 1) / 3 = 0.8333 mm.
blayout = [((0, 40), 0), ((0, 42), 0), ((0, 44), 0)]
brk = np.zeros(9)
brk[1] = 1
bpieces = ([0, 0, 2, 2, 4, 4, 4, 4, 8, 8, 8, 8], [0.5 * MM] * 4 + [1.0 * MM] * 8)
write_run(out, "breakage_s1", 300, 3e-4, 50.0, 2.0, 100.0,
          [(0.0, (blayout, np.zeros(9), np.zeros(9), np.zeros(9))),
           (3e-4, (blayout, peaks(2e5, 1)[:9], np.zeros(9), peaks(2e5, 1)[:9], brk, bpieces))])

r = subprocess.run(["/usr/bin/python3", tool, out, "--markdown", "-o", os.path.join(work, "fig")],
                   capture_output=True, text=True)
print(r.stdout)
print(r.stderr)
expect(r.returncode == 0, "paper_seeds.py exits 0")
rows = {}
for ln in r.stdout.splitlines():
    cells = [c.strip() for c in ln.strip().strip("|").split("|")]
    if ln.startswith("|") and len(cells) > 1:
        rows.setdefault(cells[0], []).append(cells[1:])


def row(name, k=0):
    return rows.get(name, [[]] * (k + 1))[k] if len(rows.get(name, [])) > k else []


e1 = row("e1e8_s1")
expect(e1[:5] == ["0.004", "1000", "11", "20.5", "2"], "e1e8_s1: time, steps, CPU (user + system), wall, peak [MPa]")
expect(e1[5] == "1", "e1e8_s1: the peak after the first interval [MPa]")
expect(e1[6:8] == ["2", "(12, -2)"], "e1e8_s1: the peak in the interval ending at 2 ms, on the fiber at (12, -2) mm")
expect(e1[8:10] == ["0.3", "0 / 24"], "e1e8_s1: the shear peak [MPa] and broken / bonds")
orient = row("e1e8_s1", 1)
want = ["%.2f (%d)" % (hand_axx[k], 2 if k in ("arm_core", "bath") else 1)
        for k in ("arm_wall", "arm_core", "nozzle_wall", "nozzle_core", "gate", "bath_wall", "bath_core", "bath")]
expect(orient == want, "orientation a_xx (N) per region equals the hand values (%s)" % orient)
b = row("breakage_s1")
expect(b[:5] == ["0.0003", "300", "52", "100", "0.2"] and b[9] == "1 / 9", "breakage_s1: cost, peak, broken bonds")
case_rows = [v for k, vs in rows.items() if k.startswith("3.8 % plate, E") for v in vs]
expect(len(case_rows) >= 1 and case_rows[0][:3] == ["2", "3 +- 1.41 (2..4)", "1"],
       "E = 1e8 over the seeds: max sigma mean +- sd (min..max) (%s)" % (case_rows[:1],))
brk_rows = [v for k, vs in rows.items() if k.startswith("breakage case") for v in vs]
expect(len(brk_rows) == 1 and brk_rows[0][3:7] == ["1", "4", "0.75", "0.833"],
       "breakage over the seeds: broken bonds, pieces, L_N, L_W (%s)" % brk_rows)
expect(row("seed 1") == ["2.00", "3.00", "1.000"] and row("seed 2") == ["3.00", "2.00", "1.000"],
       "glass / E = 1e8 per seed: CPU ratio (user + system) and wall ratio")
expect(row("all")[:2] == ["2.5 +- 0.707 (2..3)", "2.5 +- 0.707 (2..3)"], "glass / E = 1e8 over the seeds")
for suffix in ("_bonds.png", "_orientation.png", "_lengths.png"):
    p = os.path.join(work, "fig" + suffix)
    expect(os.path.isfile(p) and os.path.getsize(p) > 1000, "writes fig%s" % suffix)
# Runs that end at different times (one still going): --common analyses the
# plates at the latest time both reached, 2 ms; --time picks the plates' time
# and leaves the breakage run at its last snapshot.
part = os.path.join(work, "partial")
os.makedirs(part)
write_run(part, "e1e8_s1", 1000, 0.004, 10.0, 1.0, 20.5,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.002, (layout, peaks(2e6, 4), peaks(1e5, 4), peaks(2e6, 4))),
           (0.004, (layout, peaks(5e6, 4), peaks(3e5, 4), peaks(5e6, 4)))])
write_run(part, "glass_s1", 500, 0.002, 20.0, 2.0, 61.5,
          [(0.0, (layout, np.zeros(nb), np.zeros(nb), np.zeros(nb))),
           (0.002, (layout, peaks(8e6, 0), peaks(1e5, 0), peaks(8e6, 0)))])
write_run(part, "breakage_s1", 300, 3e-4, 50.0, 2.0, 100.0,
          [(0.0, (blayout, np.zeros(9), np.zeros(9), np.zeros(9))),
           (3e-4, (blayout, peaks(2e5, 1)[:9], np.zeros(9), peaks(2e5, 1)[:9], brk, bpieces))])
r = subprocess.run(["/usr/bin/python3", tool, part, "--markdown", "--common"], capture_output=True, text=True)
got = {}
for ln in r.stdout.splitlines():
    if ln.startswith("| e1e8_s1 |") or ln.startswith("| breakage_s1 |"):  # the first table: per run
        got.setdefault(ln.split("|")[1].strip(), [c.strip() for c in ln.strip().strip("|").split("|")][1:])
expect(r.returncode == 0 and got.get("e1e8_s1", [""])[0] == "0.002" and got["e1e8_s1"][4] == "2"
       and got.get("breakage_s1", [""])[0] == "0.0003",
       "--common: the plates at the time both reached (2 ms, peak 2 MPa), breakage at its own (%s)" % got)
r = subprocess.run(["/usr/bin/python3", tool, part, "--markdown", "--time", "0.002"], capture_output=True,
                   text=True)
expect(r.returncode == 0 and "| breakage_s1 | 0.0003 |" in r.stdout and "| e1e8_s1 | 0.002 |" in r.stdout,
       "--time: the plates' snapshot, the breakage run at its last")
r = subprocess.run(["/usr/bin/python3", tool, os.path.join(work, "empty")], capture_output=True, text=True)
expect(r.returncode == 1 and "no such directory" in r.stderr, "a missing directory: exit 1 with a message")

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
