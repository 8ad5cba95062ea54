#!/usr/bin/env python3
"""A failure on one rank ends the job, never hangs it (docs/architecture.md,
"Errors"). One scenario per call, each through `mpiexec -n 2 sphdem run`
with a fault injected by SPHDEM_INJECT_FAULT=RANK:STEP:KIND on an endless
run (end_time 1000 s), so that a hang shows up as a timeout:

  simulation   a one-rank SimulationError (as a DEM list overflow) on rank
               1 after step 5: exit 3, rank and step printed, no last state
  runtime      a std::runtime_error on rank 0 after step 5: exit 1
  snapshot_write    an HDF5 write failing on rank 1 inside the collective
               write of the snapshot of step 10: every rank agrees and exits
               1 (no abort), the cause printed once, no partial snapshot; the
               checkpoint of step 5 restarts
  checkpoint_write  the same inside the checkpoint of step 10: the
               checkpoint of step 5 intact, no temporary file, and it restarts
  restart_read      an HDF5 read failing on rank 1 inside a restart's
               collective read: refused (exit 2) on every rank, printed once;
               the checkpoint then restarts without the fault
  full_disk    a full disk: as root where a tmpfs can be mounted, the real
               thing (a 1 MiB tmpfs filling up with checkpoints); otherwise every write of
               rank 1 failing with ENOSPC from step 12 on (SPHDEM_INJECT_FAULT
               enospc). Exit 1 within seconds, the last complete checkpoint
               restarts
  no_progress  output.every_time far below the step (1e-300 s, from --set and
               from the case file): refused at once (exit 2) naming the key,
               by `run` and `check`, nothing written
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

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

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
DEADLINE = scaled(40)
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


def restarts(out_dir, steps, ranks=2):
    """A restart from the newest checkpoint (no fault) completes."""
    code, out, err, _ = run(["run", POISEUILLE, "-o", out_dir, *ENDLESS, "--restart", "latest",
                             "--steps", str(steps)], ranks=ranks)
    expect(code == 0 and "restarting from" in out,
           "the last complete checkpoint restarts (exit %s)" % code)
    return out


def leftovers(out_dir):
    """Temporary files left in the output directory and its checkpoints."""
    found = []
    for d in (out_dir, os.path.join(out_dir, "checkpoints")):
        if os.path.isdir(d):
            found += [f for f in os.listdir(d) if f.endswith(".tmp")]
    return found


def collective_io_failure(args, fault, what, cause, status=1, rank=1):
    """Every rank agrees on the failure: one message, the status, no abort."""
    code, out, err, seconds = run(args, fault=fault)
    expect(code is not None, "the job ended (no hang) within %d s" % DEADLINE)
    expect(code == status, "exit status %d (got %s)" % (status, code))
    head = "sphdem: output failed: " if status == 1 else "sphdem: error: "
    expect(err.count(head) == 1, "the failure printed once ('%s')" % head.strip())
    expect(what in err and "on rank %d" % rank in err and cause in err,
           "the file, rank %d and the cause named: '%s', '%s'" % (rank, what, cause))
    expect("MPI_ABORT" not in err and "sphdem: rank" not in err,
           "no abort: every rank left together")
    return out, err


def checkpoints_in(out_dir):
    d = os.path.join(out_dir, "checkpoints")
    return sorted(os.listdir(d)) if os.path.isdir(d) else []


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
elif scenario == "snapshot_write":
    out_dir = os.path.join(work, "out")
    collective_io_failure(["run", POISEUILLE, "-o", "out", *ENDLESS, "--checkpoint-every", "5"],
                          "1:10:snapshot_write", "snapshot '%s/poiseuille_00000010.h5'" % "out",
                          "HDF5 write dataset failed")
    expect("poiseuille_00000010.h5" not in snapshots(out_dir) and not leftovers(out_dir),
           "the failed snapshot was not published, no temporary file: %s"
           % (snapshots(out_dir) + leftovers(out_dir)))
    restarts("out", 12)
elif scenario == "checkpoint_write":
    out_dir = os.path.join(work, "out")
    collective_io_failure(["run", POISEUILLE, "-o", "out", *ENDLESS, "--checkpoint-every", "5"],
                          "1:10:checkpoint_write",
                          "checkpoint 'out/checkpoints/poiseuille_00000010.ckpt.h5'",
                          "HDF5 write dataset failed")
    expect(checkpoints_in(out_dir) == ["poiseuille_00000005.ckpt.h5"],
           "the checkpoint of step 5 intact, no other, no temporary file: %s"
           % checkpoints_in(out_dir))
    out = restarts("out", 12)
    expect("poiseuille_00000005.ckpt.h5" in out, "the restart used the checkpoint of step 5")
elif scenario == "restart_read":
    code, _, _, _ = run(["run", POISEUILLE, "-o", "out", *ENDLESS, "--checkpoint-every", "5",
                         "--steps", "10"])
    expect(code == 0, "the run that writes the checkpoints (exit %s)" % code)
    ckpt = os.path.join("out", "checkpoints", "poiseuille_00000010.ckpt.h5")
    collective_io_failure(["run", POISEUILLE, "-o", "out", *ENDLESS, "--restart", ckpt,
                           "--steps", "12"], "1:0:restart_read", ckpt,
                          "HDF5 read dataset failed", status=2)
    expect(os.path.isfile(os.path.join(work, ckpt)), "the checkpoint is still there")
    restarts("out", 12)
elif scenario == "full_disk":
    disk = os.path.join(work, "disk")
    os.makedirs(disk)
    mounted = os.geteuid() == 0 and subprocess.call(
        ["mount", "-t", "tmpfs", "-o", "size=1M", "tmpfs", disk],
        stderr=subprocess.DEVNULL) == 0
    try:
        if mounted:
            print("a real full disk: a 1 MiB tmpfs", flush=True)
            # Checkpoints pile up (keep 1000) until one does not fit.
            args = ["run", POISEUILLE, "-o", "disk/out", *ENDLESS, "--set",
                    "output.every_steps=1000", "--set", "checkpoint.keep=1000",
                    "--checkpoint-every", "5"]
            code, out, err, _ = run(args)
            expect("checkpoint '" in err, "the failing write named: a checkpoint")
        else:
            print("not root or no tmpfs: every write of rank 1 fails with ENOSPC from step 12",
                  flush=True)
            args = ["run", POISEUILLE, "-o", "disk/out", *ENDLESS, "--checkpoint-every", "5"]
            code, out, err, _ = run(args, fault="1:12:enospc")
        expect(code is not None, "the job ended (no hang) within %d s" % DEADLINE)
        expect(code == 1, "exit status 1 (got %s)" % code)
        expect(err.count("sphdem: output failed: ") == 1 and "No space left on device" in err,
               "the failure printed once, with its cause")
        expect("MPI_ABORT" not in err and "sphdem: rank" not in err,
               "no abort: every rank left together")
        expect(not leftovers(os.path.join(disk, "out")),
               "no temporary file: %s" % leftovers(os.path.join(disk, "out")))
        kept = checkpoints_in(os.path.join(disk, "out"))
        expect(len(kept) >= 1, "a checkpoint survived: %s" % kept)
        # The restart needs room: a copy of the output elsewhere.
        shutil.copytree(os.path.join(disk, "out"), os.path.join(work, "copy"))
    finally:
        if mounted:
            subprocess.call(["umount", disk])
    m = re.search(r"_(\d+)\.ckpt\.h5$", kept[-1]) if kept else None
    if m:
        out = restarts("copy", int(m.group(1)) + 2)
        expect(kept[-1] in out, "the restart used the newest checkpoint, %s" % kept[-1])
elif scenario == "no_progress":
    code, out, err, seconds = run(["run", POISEUILLE, "-o", "out", *ENDLESS, "--set",
                                   "output.every_time=1e-300"])
    expect(code == 2 and err.count("sphdem: error: --set: key 'output.every_time'") == 1
           and "more than one snapshot per step" in err,
           "run: refused with exit 2 (got %s), naming --set and the key, once" % code)
    expect(seconds < DEADLINE and not os.path.exists(os.path.join(work, "out")),
           "at once, nothing written")
    bad = os.path.join(work, "every_time.yaml")
    text = open(POISEUILLE).read()
    text = text.replace("  every_time: 0.05", "  every_time: 1.0e-300")
    with open(bad, "w") as f:
        f.write(text)
    line = text.splitlines().index("  every_time: 1.0e-300") + 1
    for command in ("run", "check"):
        code, out, err, _ = run([command, bad, "-o", "out2"] if command == "run"
                                else [command, bad])
        expect(code == 2 and ("%s:%d: key 'output.every_time'" % (bad, line)) in err,
               "%s: refused with exit 2 (got %s), naming %s:%d" % (command, code, bad, line))
    expect(not os.path.exists(os.path.join(work, "out2")), "nothing written")
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
    # Whichever rank holds the particle, every rank's message names it.
    expect(re.search(r"simulation failed: step \d+ \(t = [^)]*\): rank \d+: particle \d+ ", err)
           is not None, "the failing particle named, with its rank: %s" % err.strip()[-300:])
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
