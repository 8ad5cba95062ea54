#!/usr/bin/env python3
"""End-to-end checks of checkpoint/restart through `sphdem run`
(docs/checkpoint.md). One scenario per call:

  sigterm         SIGTERM to a 1-rank run and to ONE rank of a 2-rank run:
                  each writes a checkpoint and exits 0; restarts (on 1 and 3
                  ranks) match a straight run bitwise, XDMF included
  sigusr1         SIGUSR1 to mpiexec (it forwards it), with -q: the same,
                  the stopped-by-signal line printed all the same
  sigterm_mpiexec SIGTERM to mpiexec, which Open MPI does not forward (it
                  ends the job): the job ends, status 0 only with the
                  stopped-by-signal line, a checkpoint written restarts
  sigkill         SIGKILL of one rank of a 2-rank run writing a checkpoint
                  every 20 steps: `--restart latest` completes and matches
  abort_in_write  a crash between the data write and the rename
                  (SPHDEM_TEST_ABORT_IN_CHECKPOINT=2): the previous
                  checkpoint is intact and the restart uses it
  dem             a fibers-only run (inputs/fibers_only.yaml): a checkpoint on
                  2 ranks, restarted on 3, matches a straight run on 1 (every
                  numeric DEM field bitwise; bond and contact slots are
                  opaque records whose padding bytes are undefined, so they
                  are checked through the motion they drive)
  dem3d           the 3D fibers-only run (inputs/fibers_only_3d.yaml, its
                  mold as rectangle walls): a checkpoint on 2 ranks,
                  restarted on 1, matches a straight run on 1
  refused         truncated, corrupt, another case's, other physics, another
                  format; `latest` skips a corrupt newest one; an output
                  directory in use needs --restart or --overwrite

The case is Poiseuille flowing along its periodic axis (positions wrap).
Runs that are stopped by a signal are "endless" (end_time 1000 s), so the
signal always lands mid-run, whatever the machine's speed: no timing enters
any check, only timeouts.

usage: check_checkpoint.py SCENARIO SPHDEM SOURCE_DIR WORK_DIR MPIEXEC [MPIEXEC_FLAGS...]
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) < 6 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)

scenario, exe, src, work, mpiexec = sys.argv[1:6]
mpi_flags = sys.argv[6:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
case = os.path.join(src, "inputs", "validation", "poiseuille.yaml")
FLOW = ["--set", "initial_velocity=[0.01,0]", "--set", "resin.sound_speed=0.1",
        "--set", "output.every_steps=10", "--set", "output.progress_every=100000"]
ENDLESS = ["--set", "numerics.end_time=1000"]
failures = []
checks = 0


def expect(cond, what):
    global checks
    checks += 1
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def command(args, ranks):
    if ranks is None:
        return [exe, *args]
    return [mpiexec, "-n", str(ranks), *mpi_flags, exe, *args]


def env_with(extra=None):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.update(extra or {})
    return env


def run(args, ranks=None, env=None):
    p = subprocess.run(command(args, ranks), capture_output=True, text=True, cwd=work,
                       timeout=scaled(150), env=env_with(env))
    return p.returncode, p.stdout, p.stderr


def start(args, ranks=None):
    return subprocess.Popen(command(args, ranks), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=work, env=env_with(), start_new_session=True)


def wait_for(path, proc, timeout=120):
    """Waits until `path` exists (or the process ends)."""
    timeout = scaled(timeout)
    t0 = time.monotonic()
    while not glob.glob(path):
        if proc.poll() is not None or time.monotonic() - t0 > timeout:
            return False
        time.sleep(0.02)
    return True


def sphdem_ranks(root_pid):
    """PIDs of the sphdem processes below root_pid (mpiexec's children)."""
    children = {}
    for stat in glob.glob("/proc/[0-9]*/stat"):
        try:
            text = open(stat).read()
        except OSError:
            continue
        name = text[text.index("(") + 1:text.rindex(")")]
        ppid = int(text[text.rindex(")") + 2:].split()[1])
        children.setdefault(ppid, []).append((int(stat.split("/")[2]), name))
    out, todo = [], [root_pid]
    while todo:
        for pid, name in children.get(todo.pop(), []):
            todo.append(pid)
            if name == "sphdem":
                out.append(pid)
    return sorted(out)


def checkpoints(out):
    files = glob.glob(os.path.join(work, out, "checkpoints", "poiseuille_*.ckpt.h5"))
    return sorted(int(re.search(r"_(\d+)\.ckpt\.h5$", f).group(1)) for f in files)


def straight(steps):
    """A straight 1-rank run to `steps` (the reference)."""
    out = "straight_%d" % steps
    if not os.path.exists(os.path.join(work, out)):
        code, _, err = run(["run", case, "-o", out, "--steps", str(steps), *FLOW, "-q"])
        expect(code == 0, "straight run to step %d: %s" % (steps, err.strip()))
    return out


def same_output(a, b, step):
    """Final snapshots bitwise equal and the XDMF series identical."""
    name = "poiseuille_%08d.h5" % step
    fa = h5py.File(os.path.join(work, a, name), "r")
    fb = h5py.File(os.path.join(work, b, name), "r")
    diffs = []
    for group in fb:
        for ds in fb[group]:
            if isinstance(fb[group][ds], h5py.Dataset):
                x, y = fa[group][ds][()], fb[group][ds][()]
                if x.shape != y.shape or x.tobytes() != y.tobytes():
                    diffs.append(group + "/" + ds)
    expect(not diffs, "%s and %s: step %d bitwise equal %s" % (a, b, step, diffs))
    xa = open(os.path.join(work, a, "poiseuille.xdmf")).read()
    xb = open(os.path.join(work, b, "poiseuille.xdmf")).read()
    expect(xa == xb, "%s continues the XDMF series of a straight run (no gap, no duplicate)" % a)


def restart_and_compare(out, ranks, extra_steps=30):
    """Restarts `out` from its latest checkpoint, runs on, compares."""
    k = checkpoints(out)[-1]
    target = k + extra_steps
    code, stdout, err = run(["run", case, "-o", out, "--restart", "latest", "--steps", str(target),
                             *FLOW], ranks)
    expect(code == 0 and ("restarting from" in stdout and "%08d" % k in stdout),
           "%s restarts from step %d on %s rank(s): %s" % (out, k, ranks or 1, err.strip()))
    same_output(out, straight(target), target)


def stop_with(sig, out, ranks, target, extra=()):
    """Starts an endless run, signals `target(proc)` once a snapshot is out."""
    proc = start(["run", case, "-o", out, *FLOW, *ENDLESS, *extra], ranks)
    ok = wait_for(os.path.join(work, out, "poiseuille_00000020.h5"), proc)
    expect(ok, "%s: the run is under way" % out)
    for pid in target(proc):
        os.kill(pid, sig)
    stdout, stderr = proc.communicate(timeout=scaled(120))
    expect(proc.returncode == 0, "%s: exit status 0 after signal %d (got %d) %s"
           % (out, sig, proc.returncode, stderr.strip()[-300:]))
    expect("stopped by signal %d" % sig in stdout and "--restart latest" in stdout,
           "%s: says it stopped and how to continue" % out)
    expect(len(checkpoints(out)) == 1 and checkpoints(out)[0] >= 20,
           "%s: one checkpoint, written at the stop: %s" % (out, checkpoints(out)))


if scenario == "sigterm":
    stop_with(signal.SIGTERM, "term1", None, lambda p: [p.pid])
    restart_and_compare("term1", None)
    # One rank only: the other learns it at the next step and stops with it.
    stop_with(signal.SIGTERM, "term2", 2, lambda p: sphdem_ranks(p.pid)[:1])
    restart_and_compare("term2", 3)

elif scenario == "sigusr1":
    # mpiexec forwards SIGUSR1; -q: the stopped-by-signal line all the same
    # (job scripts look for it).
    stop_with(signal.SIGUSR1, "usr1", 2, lambda p: [p.pid], extra=["-q"])
    restart_and_compare("usr1", 1)

elif scenario == "sigterm_mpiexec":
    # Open MPI's mpirun does not forward SIGTERM: it ends the job (SIGTERM to
    # the ranks, SIGKILL a second later) and exits 1, whatever the ranks do
    # (docs/checkpoint.md: send SIGUSR1 to mpirun). What holds: the job ends,
    # a status 0 comes only with the stopped-by-signal line, and a checkpoint
    # the ranks managed to write is complete and restarts.
    proc = start(["run", case, "-o", "term_mpi", *FLOW, *ENDLESS, "-q"], 2)
    expect(wait_for(os.path.join(work, "term_mpi", "poiseuille_00000020.h5"), proc),
           "term_mpi: the run is under way")
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=scaled(120))
    print("mpiexec exit status after SIGTERM: %d" % proc.returncode)
    expect(proc.returncode != 0 or "stopped by signal 15" in stdout,
           "term_mpi: status 0 only with the stopped-by-signal line")
    if checkpoints("term_mpi"):
        restart_and_compare("term_mpi", 2)

elif scenario == "sigkill":
    proc = start(["run", case, "-o", "kill", "--checkpoint-every", "20", *FLOW, *ENDLESS], 2)
    # Any checkpoint from step 40 on: a fast run may already have pruned
    # step 40's (keep) by the time we look.
    t0 = time.monotonic()
    while not [k for k in checkpoints("kill") if k >= 40]:
        if proc.poll() is not None or time.monotonic() - t0 > scaled(120):
            break
        time.sleep(0.02)
    expect([k for k in checkpoints("kill") if k >= 40], "the run wrote its second checkpoint")
    victims = sphdem_ranks(proc.pid)
    expect(len(victims) == 2, "found both ranks: %s" % victims)
    os.kill(victims[-1], signal.SIGKILL)
    proc.communicate(timeout=scaled(120))
    expect(proc.returncode != 0, "mpiexec reports the killed rank (status %d)" % proc.returncode)
    restart_and_compare("kill", 1)

elif scenario == "abort_in_write":
    code, _, _ = run(["run", case, "-o", "abort", "--steps", "100", "--checkpoint-every", "20",
                      *FLOW, "-q"], 2, env={"SPHDEM_TEST_ABORT_IN_CHECKPOINT": "2"})
    ck = os.path.join(work, "abort", "checkpoints")
    expect(code != 0, "the run dies in its second checkpoint (status %d)" % code)
    expect(checkpoints("abort") == [20], "only the first checkpoint is published: %s"
           % os.listdir(ck))
    expect(os.path.exists(os.path.join(ck, ".poiseuille_00000040.ckpt.h5.tmp")),
           "the interrupted write left only its temporary file")
    restart_and_compare("abort", 2)
    expect(not any(f.endswith(".tmp") for f in os.listdir(ck)),
           "the restart cleans up the stale temporary file")

elif scenario == "refused":
    code, _, err = run(["run", case, "-o", "good", "--steps", "20", "--checkpoint-every", "10",
                        *FLOW, "-q"])
    expect(code == 0 and checkpoints("good") == [10, 20], "two checkpoints: " + err.strip())
    good = os.path.join(work, "good", "checkpoints", "poiseuille_00000020.ckpt.h5")

    def refused(path, why, args=(), what=""):
        shutil.rmtree(os.path.join(work, "r"), ignore_errors=True)
        code, _, err = run(["run", case, "-o", "r", "--restart", path, *FLOW, *args, "-q"], 2)
        expect(code == 2 and why in err and path in err,
               "%s: exit 2, message names the file and says '%s': %s"
               % (what, why, err.strip()[-400:]))

    trunc = os.path.join(work, "truncated.ckpt.h5")
    data = open(good, "rb").read()
    open(trunc, "wb").write(data[:len(data) // 2])
    refused(trunc, "truncated or corrupt", what="truncated")

    corrupt = os.path.join(work, "corrupt.ckpt.h5")
    shutil.copy(good, corrupt)
    with h5py.File(corrupt, "r") as f:
        offset = f["sph/rho"].id.get_offset() + 8 * 100 + 3
    with open(corrupt, "r+b") as f:
        f.seek(offset)
        byte = f.read(1)
        f.seek(offset)
        f.write(bytes([byte[0] ^ 0x10]))
    refused(corrupt, "field 'sph/rho' fails its checksum", what="corrupt data")

    code, _, err = run(["run", os.path.join(src, "inputs", "plate.yaml"), "-o", "plate", "--steps",
                        "1", "--checkpoint-every", "1", "--set", "numerics.spacing=6e-4", "-q"])
    expect(code == 0, "a plate checkpoint: " + err.strip())
    plate = os.path.join(work, "plate", "checkpoints", "plate_00000001.ckpt.h5")
    refused(plate, "belongs to case 'plate', not 'poiseuille'", what="another case")
    refused(good, "resin.viscosity is 0.001 there, 0.002 here",
            ["--set", "resin.viscosity=2e-3"], what="other physics")

    future = os.path.join(work, "future.ckpt.h5")
    shutil.copy(good, future)
    with h5py.File(future, "r+") as f:
        f.attrs.modify("format", np.int64(999))
    refused(future, "checkpoint format 999", what="another format")
    refused(os.path.join(work, "missing.ckpt.h5"), "no such checkpoint file", what="missing")

    # latest: a corrupt newest checkpoint is skipped (said so), the older used.
    with open(good, "r+b") as f:
        f.seek(offset)
        f.write(bytes([byte[0] ^ 0x10]))
    code, out, err = run(["run", case, "-o", "good", "--restart", "latest", "--steps", "30",
                          *FLOW], 2)
    expect(code == 0 and "skipping an unusable checkpoint" in out and "fails its checksum" in out
           and "poiseuille_00000010.ckpt.h5" in out,
           "latest falls back to the older checkpoint: " + (out + err).strip()[-400:])

    code, _, err = run(["run", case, "-o", "good", "--steps", "5", *FLOW, "-q"])
    expect(code == 2 and "holds the output of an earlier run" in err and "--overwrite" in err,
           "an output directory in use is refused: " + err.strip())
    code, _, err = run(["run", case, "-o", "good", "--steps", "5", "--overwrite", *FLOW, "-q"])
    files = sorted(os.listdir(os.path.join(work, "good")))
    expect(code == 0 and "checkpoints" not in files and "poiseuille_00000010.h5" not in files
           and "poiseuille_00000005.h5" in files,
           "--overwrite replaces the earlier run: %s %s" % (files, err.strip()))
    code, _, err = run(["run", case, "-o", "good", "--overwrite", "--restart", "latest", "-q"])
    expect(code == 2 and "excludes" in err, "--overwrite and --restart exclude each other")

elif scenario == "dem":
    fibers = os.path.join(src, "inputs", "fibers_only.yaml")
    DEM = ["--set", "moving_walls[0].velocity_table=[[0,0,-10]]",
           "--set", "fibers.region.box.min=[-0.015,0.050]", "--set", "output.every_steps=1000", "-q"]
    code, _, err = run(["run", fibers, "-o", "dem_straight", "--steps", "6000",
                        "--checkpoint-every", "6000", *DEM])
    expect(code == 0, "straight DEM run: " + err.strip())
    code, _, err = run(["run", fibers, "-o", "dem", "--steps", "3000", "--checkpoint-every", "3000",
                        *DEM], 2)
    expect(code == 0, "DEM run to a checkpoint on 2 ranks: " + err.strip())
    code, _, err = run(["run", fibers, "-o", "dem", "--steps", "6000", "--restart", "latest",
                        "--checkpoint-every", "6000", *DEM], 3)
    expect(code == 0, "DEM restart on 3 ranks: " + err.strip())
    name = "checkpoints/fibers_only_00006000.ckpt.h5"
    a = h5py.File(os.path.join(work, "dem", name), "r")["dem"]
    b = h5py.File(os.path.join(work, "dem_straight", name), "r")["dem"]
    numeric = [k for k in b if b[k].attrs["type"] != 4]
    diffs = [k for k in numeric if a[k][()].tobytes() != b[k][()].tobytes()]
    expect(len(numeric) >= 10 and not diffs, "every numeric DEM field bitwise equal: %s differ" % diffs)
    # The histories mattered: some contacts (first int64 of each 32-byte
    # 2D slot: the partner, >= 0 a particle, < -1 a wall) are active.
    slots = np.concatenate([b[k][()].reshape(-1, 32)[:, :8].copy().view(np.int64).ravel()
                            for k in ("contacts", "wall_contacts")])
    expect(np.count_nonzero(slots != -1) > 0, "contacts were active at the restart's end")
    xa = open(os.path.join(work, "dem", "fibers_only.xdmf")).read()
    xb = open(os.path.join(work, "dem_straight", "fibers_only.xdmf")).read()
    expect(xa == xb, "the DEM run continues the XDMF series")

elif scenario == "dem3d":
    fibers = os.path.join(src, "inputs", "fibers_only_3d.yaml")
    DEM = ["--set", "output.every_steps=5000", "-q"]
    code, _, err = run(["run", fibers, "-o", "straight", "--steps", "20000",
                        "--checkpoint-every", "20000", *DEM])
    expect(code == 0, "straight 3D DEM run: " + err.strip())
    code, _, err = run(["run", fibers, "-o", "dem", "--steps", "10000", "--checkpoint-every",
                        "10000", *DEM], 2)
    expect(code == 0, "3D DEM run to a checkpoint on 2 ranks: " + err.strip())
    code, _, err = run(["run", fibers, "-o", "dem", "--steps", "20000", "--restart", "latest",
                        "--checkpoint-every", "20000", *DEM])
    expect(code == 0, "3D DEM restart on 1 rank: " + err.strip())
    name = "checkpoints/fibers_only_3d_00020000.ckpt.h5"
    fa = h5py.File(os.path.join(work, "dem", name), "r")
    fb = h5py.File(os.path.join(work, "straight", name), "r")
    a, b = fa["dem"], fb["dem"]
    numeric = [k for k in b if b[k].attrs["type"] != 4]
    diffs = [k for k in numeric if a[k][()].tobytes() != b[k][()].tobytes()]
    expect(len(numeric) >= 10 and not diffs, "every numeric DEM field bitwise equal: %s differ" % diffs)
    walls = fb.attrs["dem_walls"]
    expect(walls[0] == 2 and fa.attrs["dem_walls"].tobytes() == walls.tobytes(),
           "the rectangle walls' state (the piston moved) is the same")
    # Wall contacts were active (first int64 of each 32-byte slot: a wall
    # key, < -1), so their histories went through the checkpoint.
    keys = b["wall_contacts"][()].reshape(-1, 32)[:, :8].copy().view(np.int64).ravel()
    expect(np.count_nonzero(keys < -1) > 0, "wall contacts were active at the restart's end")
    xa = open(os.path.join(work, "dem", "fibers_only_3d.xdmf")).read()
    xb = open(os.path.join(work, "straight", "fibers_only_3d.xdmf")).read()
    expect(xa == xb, "the 3D DEM run continues the XDMF series")

else:
    print("unknown scenario " + scenario)
    sys.exit(2)

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
