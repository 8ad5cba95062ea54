#!/usr/bin/env python3
"""End-to-end checks of the sphdem command line: exit statuses, error
messages that name file, line and key, nothing written on bad input, --steps,
--set, `check`, and a blow-up that stops with a message and its last state.

usage: check_cli.py SPHDEM_BINARY SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) != 4 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)

exe, src, work = sys.argv[1:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []
checks = 0


def run(*args):
    p = subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=scaled(300))
    return p.returncode, p.stdout, p.stderr


def expect(cond, what):
    global checks
    checks += 1
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


pois = os.path.join(src, "inputs", "validation", "poiseuille.yaml")

code, out, err = run("--help")
expect(code == 0 and "run" in out and "check" in out, "--help lists the sub-commands")
code, out, err = run("run", "--help")
expect(code == 0 and "--steps" in out and "--set" in out, "run --help lists its options")

bad = write("bad.yaml", open(pois).read().replace("  density: 1000", "  densty: 1000"))
code, out, err = run("run", bad, "-o", "bad_out")
expect(code == 2, "unknown key exits with status 2")
expect("bad.yaml:7" in err and "resin.densty" in err and "did you mean" in err,
       "unknown key message names file:line and key: " + err.strip())
expect(not os.path.exists(os.path.join(work, "bad_out")), "nothing written on bad input")

code, out, err = run("run", pois, "-o", "set_out", "--set", "resin.density=-5")
expect(code == 2 and "--set" in err and "resin.density" in err and "positive" in err,
       "bad --set value is reported against --set: " + err.strip())

code, out, err = run("run", os.path.join(work, "missing.yaml"))
expect(code == 2 and "cannot open" in err, "missing case file exits 2")

code, out, err = run("check", os.path.join(src, "inputs", "plate.yaml"))
expect(code == 0 and "10000 resin" in out and "time step" in out and "memory" in out,
       "check prints counts, time step and estimates")
expect("keys not at their default" in out and "resin.density = 900" in out
       and "numerics.cfl =" not in out,
       "check prints the keys not at their default, from the schema")

code, out, err = run("keys")
expect(code == 0 and "fibers.void_fraction_in_continuity" in out
       and "moving_walls[].velocity_table" in out and "required" in out,
       "keys lists every key with its default")
code, out, err = run("keys", "--markdown")
expect(code == 0 and out.startswith("# Case files") and "| `density` | number | kg/m^3 |" in out,
       "keys --markdown prints the reference page")

code, out, err = run("run", pois, "-o", "run_out", "--steps", "50",
                     "--set", "output.every_steps=25", "--set", "output.progress_every=10")
expect(code == 0, "run --steps 50 succeeds: " + err.strip())
expect("step       50" in out and "particle-steps/s" in out and "ETA" in out,
       "progress line shows step, rate and ETA")
files = sorted(os.listdir(os.path.join(work, "run_out")))
expect("poiseuille.xdmf" in files and "poiseuille_00000050.h5" in files
       and "poiseuille_00000000.h5" in files and "case.yaml" in files,
       "snapshots at steps 0, 25, 50, the XDMF and the case file: %s" % files)
expect(not any(f.endswith(".tmp") for f in files), "no temporary files left")

# The effective case: the overrides are in the output's case.yaml, which
# runs as it is, and in every snapshot.
effective = open(os.path.join(work, "run_out", "case.yaml")).read()
expect("every_steps: 25" in effective and "progress_every: 10" in effective
       and "name: poiseuille" in effective and "# --set output.every_steps=25" in effective,
       "case.yaml holds the effective case with the overrides")
code, out, err = run("check", os.path.join(work, "run_out", "case.yaml"))
expect(code == 0 and "case 'poiseuille'" in out and "output.every_steps = 25" in out,
       "the effective case.yaml checks as the same case: " + err.strip())
import h5py  # noqa: E402 (only this check needs it)
with h5py.File(os.path.join(work, "run_out", "poiseuille_00000050.h5"), "r") as f:
    stored = f.attrs["case_yaml"]
    stored = stored.decode() if isinstance(stored, bytes) else str(stored)
expect(stored == effective, "the snapshot's case_yaml attribute is the effective case")

blow = write("blowup.yaml", """
dimension: 2
resin: {density: 1000, viscosity: 0, sound_speed: 1.0}
numerics: {spacing: 1.0e-3, end_time: 1.0, anti_clump: false}
mold: {wall_layers: 1, shapes: [{box: {min: [0, 0], max: [0.01, 0.01]}}]}
fill: [{box: {min: [0, 0], max: [0.01, 0.01]}}]
initial_velocity: [40, 0]
output: {every_time: 0.5}
""")
code, out, err = run("run", blow, "-o", "blow_out")
expect(code == 3, "a run that blows up exits with status 3 (got %d)" % code)
expect("simulation failed" in err and ("left the domain" in err or "not finite" in err),
       "blow-up message says what happened: " + err.strip())
expect("last state written" in out, "the last state is written")

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
