#!/usr/bin/env python3
"""A failure on one rank ends the job, never hangs it (docs/architecture.md,
"Errors"). One scenario per call, each through `mpiexec -n 2 sphdem run`
with a fault injected by SPHDEM_INJECT_FAULT=RANK:STEP:KIND on an endless
run (end_time 1000 s), so that a hang shows up as a timeout:

  simulation   a one-rank SimulationError (as a DEM list overflow) on rank
               1 after step 5: exit 3, rank and step printed, no last state
  runtime      a std::runtime_error on rank 0 after step 5: exit 1
  hdf5         an HDF5 call failing on rank 1 inside the collective write
               of the snapshot of step 10: exit 1
  input        rank 1 alone fails to load the case: every rank agrees,
               exit 2, the cause printed once, nothing written
  dem          a fibers-only run (the other driver), rank 1 after step 3:
               exit 3
  blowup       a collective failure (the resin blows up, both ranks see
               it): exit 3, the last state written, no abort
  bad_input    a bad key on both ranks: exit 2, printed once; the same for
               a malformed SPHDEM_INJECT_FAULT
  one_rank     the injected SimulationError on a 1-rank run: with one rank
               every failure is collective, so exit 3 with the last state

usage: check_faults.py SCENARIO SPHDEM SOURCE_DIR WORK_DIR MPIEXEC [MPIEXEC_FLAGS...]
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time

if len(sys.argv) < 6 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)

scenario, exe, src, work, mpiexec = sys.argv[1:6]
mpi_flags = sys.argv[6:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
POISEUILLE = os.path.join(src, "inputs", "validation", "poiseuille.yaml")
ENDLESS = ["--set", "numerics.end_time=1000", "--set", "output.every_steps=10",
           "--set", "output.progress_every=100000"]
# A hang fails here, well inside ctest's timeout; a one-rank failure takes
# about a second after the start-up.
DEADLINE = 40
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(args, ranks=2, fault=None):
    """Runs sphdem; returns (exit status or None after a hang, stdout, stderr, seconds)."""
    cmd = [mpiexec, "-n", str(ranks), *mpi_flags, exe, *args]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.pop("SPHDEM_INJECT_FAULT", None)
    if fault:
        env["SPHDEM_INJECT_FAULT"] = fault
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         cwd=work, env=env, start_new_session=True)
    try:
        out, err = p.communicate(timeout=DEADLINE)
        code = p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        code = None
    seconds = time.monotonic() - t0
    print("$ %s%s\n  exit %s after %.1f s" % ("SPHDEM_INJECT_FAULT=%s " % fault if fault else "",
                                            " ".join(cmd), code, seconds))
    print("  stderr: " + err.strip().replace("\n", "\n          ")[:3000], flush=True)
    return code, out, err, seconds


def snapshots(out_dir):
    if not os.path.isdir(out_dir):
        return []
    return sorted(f for f in os.listdir(out_dir) if f.endswith(".h5"))


def one_rank_failure(args, fault, status, rank, step, cause):
    code, out, err, seconds = run(args, fault=fault)
    expect(code is not None, "the job ended (no hang) within %d s" % DEADLINE)
    expect(code == status, "exit status %d (got %s)" % (status, code))
    expect("sphdem: rank %d, step %d: " % (rank, step) in err,
           "rank %d and step %d printed" % (rank, step))
    expect(cause in err, "the cause printed: '%s'" % cause)
    expect("last state written" not in out, "no collective write after a one-rank failure")
    return out, err


if scenario == "simulation":
    one_rank_failure(["run", POISEUILLE, "-o", "out", *ENDLESS], "1:5:simulation", 3, 1,
                     5, "fault injected after step 5")
elif scenario == "runtime":
    one_rank_failure(["run", POISEUILLE, "-o", "out", *ENDLESS], "0:5:runtime", 1, 0, 5,
                     "fault injected after step 5")
elif scenario == "hdf5":
    one_rank_failure(["run", POISEUILLE, "-o", "out", *ENDLESS], "1:10:hdf5", 1, 1, 10,
                     "HDF5 write dataset (injected fault) failed")
    expect("poiseuille_00000010.h5" not in snapshots(os.path.join(work, "out")),
           "the failed snapshot was not published")
elif scenario == "dem":
    one_rank_failure(["run", os.path.join(src, "inputs", "fibers_only.yaml"), "-o", "out",
                      *ENDLESS], "1:3:simulation", 3, 1, 3, "fault injected after step 3")
elif scenario == "input":
    code, out, err, _ = run(["run", POISEUILLE, "-q", "-o", "out", *ENDLESS], fault="1:0:input")
    expect(code == 2, "exit status 2 (got %s)" % code)
    expect(err.count("sphdem: error:") == 1 and "on rank 1: " in err
           and "fault injected" in err, "the cause printed once, by rank 0")
    expect(not os.path.exists(os.path.join(work, "out")), "nothing written")
elif scenario == "blowup":
    blow = os.path.join(work, "blowup.yaml")
    with open(blow, "w") as f:
        f.write("""dimension: 2
name: blowup
resin: {density: 1000, viscosity: 0, sound_speed: 1.0}
numerics: {spacing: 1.0e-3, end_time: 1.0, anti_clump: false}
mold: {wall_layers: 1, shapes: [{box: {min: [0, 0], max: [0.01, 0.01]}}]}
fill: [{box: {min: [0, 0], max: [0.01, 0.01]}}]
initial_velocity: [40, 0]
output: {every_time: 0.5}
""")
    code, out, err, _ = run(["run", blow, "-o", "out"])
    expect(code == 3, "exit status 3 (got %s)" % code)
    m = re.search(r"simulation failed: .*?step (\d+)", err)
    expect(m is not None and err.count("simulation failed") == 1,
           "the cause printed once, with its step")
    expect("MPI_ABORT" not in err and "sphdem: rank" not in err, "no abort")
    expect("last state written" in out, "the last state is written")
    if m:
        last = "blowup_%08d.h5" % int(m.group(1))
        expect(last in snapshots(os.path.join(work, "out")),
               "%s on disk: %s" % (last, snapshots(os.path.join(work, "out"))))
elif scenario == "bad_input":
    bad = os.path.join(work, "bad.yaml")
    with open(bad, "w") as f:
        f.write(open(POISEUILLE).read().replace("  density: 1000", "  densty: 1000"))
    code, out, err, _ = run(["run", bad, "-o", "out"])
    expect(code == 2, "exit status 2 (got %s)" % code)
    expect(err.count("sphdem: error:") == 1 and "resin.densty" in err, "printed once, with the key")
    expect("MPI_ABORT" not in err, "no abort")
    expect(not os.path.exists(os.path.join(work, "out")), "nothing written")
    code, out, err, _ = run(["run", POISEUILLE, "-o", "out2"], fault="1:five:simulation")
    expect(code == 2 and err.count("SPHDEM_INJECT_FAULT: '1:five:simulation'") == 1,
           "a malformed SPHDEM_INJECT_FAULT is bad input (exit 2, printed once)")
elif scenario == "one_rank":
    code, out, err, _ = run(["run", POISEUILLE, "-o", "out", *ENDLESS], ranks=1,
                            fault="0:5:simulation")
    expect(code == 3, "exit status 3 (got %s)" % code)
    expect("simulation failed: fault injected after step 5" in err, "the cause printed")
    expect("last state written" in out
           and "poiseuille_00000005.h5" in snapshots(os.path.join(work, "out")),
           "the last state (step 5) is written")
else:
    print("unknown scenario " + scenario)
    sys.exit(2)

print("%s: %s" % (scenario, "FAILED: " + "; ".join(failures) if failures else "passed"))
sys.exit(1 if failures else 0)
