#!/usr/bin/env python3
"""Hostile input through the command line (issue 15). One scenario per call:

  size        defect 3: `check inputs/plate.yaml --set numerics.spacing=1e-6`
              and `run` of it are refused in seconds, exit 2, with the
              estimate and the key; --max-memory below the estimate refuses
              the plain plate; check prints the estimate
  files       defects 6 and 8 through `sphdem check`: a name with '/',
              /dev/zero, a directory, binary junk (no raw bytes echoed), a
              second document, fibers.diameter 1e-300 (exit 2, not 3),
              fibers.dt_safety 1e-300 (refused) and 1.5 (a warning), a
              self-intersecting polygon; on 2 ranks an input error is
              printed once
  restart     defect 7 (and 8's stale temporary): a checkpoint's attributes
              edited with h5py (step -5, time nan or 1e300, dt 0, a step
              that disagrees with the file name, counts out of range) are
              refused with exit 2 naming the attribute, and nothing is
              deleted: every snapshot and checkpoint is still there; a stale
              checkpoint temporary is gone after a refused restart

usage: check_hostile_input.py SCENARIO SPHDEM SOURCE_DIR WORK_DIR MPIEXEC [MPIEXEC_FLAGS...]
"""
import glob
import os
import re
import shutil
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
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(args, ranks=None, timeout=120):
    cmd = [exe, *args] if ranks is None else [mpiexec, "-n", str(ranks), *mpi_flags, exe, *args]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.monotonic()
    timeout = scaled(timeout)
    try:
        p = subprocess.run(cmd, capture_output=True, cwd=work, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None, "", f"(no end within {timeout:.0f} s)", time.monotonic() - t0
    # Bytes that are not UTF-8 become U+FFFD: not printable, counted below.
    return (p.returncode, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace"),
            time.monotonic() - t0)


def write(name, data):
    path = os.path.join(work, name)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    return path


def refused(args, message, what, ranks=None):
    code, out, err, _ = run(args, ranks)
    expect(code == 2 and message in err, f"{what}: exit {code}, stderr: {err.strip()[-300:]}")
    return err


plate = os.path.join(src, "inputs", "plate.yaml")
fibers_only = os.path.join(src, "inputs", "fibers_only.yaml")

if scenario == "size":
    fine = ["--set", "numerics.spacing=1e-6"]
    code, out, err, seconds = run(["check", plate, *fine])
    expect(code == 2 and "--set: key 'numerics.spacing': the case needs about" in err and
           "resin" in err and seconds < scaled(20),
           f"check at spacing 1e-6 refused in {seconds:.1f} s: exit {code}, {err.strip()}")
    code, out, err, seconds = run(["run", plate, "-o", "run_out", *fine])
    expect(code == 2 and "the case needs about" in err and not os.path.exists(
        os.path.join(work, "run_out")), f"run at spacing 1e-6 refused, nothing written: {err}")
    code, out, err, _ = run(["check", plate, "--max-memory", "1M"])
    expect(code == 2 and f"{plate}:" in err and "key 'numerics.spacing'" in err and
           "of --max-memory" in err, f"--max-memory 1M refuses the plate: {err.strip()}")
    code, out, err, _ = run(["check", plate, "--max-memory", "lots"])
    expect(code == 2 and "--max-memory" in err, f"--max-memory lots is bad input: {err.strip()}")
    code, out, err, _ = run(["check", plate])
    expect(code == 0 and "memory: about" in out and "estimated before building" in out,
           "check prints the estimate: " + next(
               (l for l in out.splitlines() if "memory" in l), out[-200:]))
    code, out, err, _ = run(["check", fibers_only, "--set", "fibers.area_fraction=0.3",
                             "--set", "fibers.count=~", "--set", "fibers.diameter=1e-8"])
    expect(code == 2 and "fibers." in err and "the case needs about" in err,
           f"fibers by area fraction at 10 nm refused: {err.strip()}")

elif scenario == "files":
    text = open(plate).read()

    def line_of(needle):  # the 1-based line of the case file that holds needle
        return text[:text.index(needle)].count("\n") + 1

    path = write("slash.yaml", text.replace("name: plate", "name: ../escape"))
    refused(["check", path], f"{path}:{line_of('name: plate')}: key 'name': '../escape' is not a file-name-safe",
            "a name with '/'")
    refused(["check", "/dev/zero"], "/dev/zero: not a regular file", "/dev/zero")
    os.makedirs(os.path.join(work, "a_dir"))
    refused(["check", os.path.join(work, "a_dir")], "is a directory", "a directory")
    junk = write("junk.yaml", bytes(range(256)) * 4)
    code, out, err, _ = run(["check", junk])
    # Printable UTF-8 only: no C0 or C1 control character but the newline.
    raw = [ch for ch in err
           if ch != "\n" and (ord(ch) < 0x20 or 0x7f <= ord(ch) < 0xa0 or ch == "\ufffd")]
    expect(code == 2 and junk + ":1:" in err and not raw,
           f"binary junk: exit {code}, raw bytes {raw[:8]}, stderr {err.strip()[:200]!r}")
    path = write("two_docs.yaml", text + "---\nname: second\n")
    refused(["check", path], "a second YAML document", "a second document")
    fib = open(fibers_only).read()
    path = write("diameter.yaml", fib.replace("diameter: 2.5e-4", "diameter: 1e-300"))
    refused(["check", path], "key 'fibers.diameter': must be in [1e-09, 1]", "diameter 1e-300")
    path = write("dt_tiny.yaml", re.sub(r"dt_safety: [0-9.e-]+", "dt_safety: 1e-300", fib))
    refused(["check", path], "key 'fibers.dt_safety': must be in [0.001, 2)", "dt_safety 1e-300")
    path = write("dt_big.yaml", re.sub(r"dt_safety: [0-9.e-]+", "dt_safety: 1.5", fib))
    code, out, err, _ = run(["check", path])
    expect(code == 0 and "sphdem: warning: fibers.dt_safety = 1.5 is above 1.2" in err,
           f"dt_safety 1.5: a warning: exit {code}, {err.strip()}")
    path = write("bowtie.yaml", text.replace(
        "[[-0.015, 0.030], [-0.003, 0.005], [0.003, 0.005], [0.015, 0.030]]",
        "[[-0.015, 0.030], [0.003, 0.005], [-0.003, 0.005], [0.015, 0.030]]"))
    refused(["check", path], f"{path}:{line_of('[[-0.015, 0.030], [-0.003')}: key 'mold.shapes[1].polygon': "
            "polygon intersects itself",
            "a self-intersecting nozzle")
    # Every rank reads the case; the error is printed once.
    err = refused(["check", path], "polygon intersects itself", "2 ranks", ranks=2)
    expect(err.count("intersects itself") == 1 and "rank 1" not in err,
           f"2 ranks: the error once: {err.strip()}")

elif scenario == "restart":
    import h5py
    case = os.path.join(src, "inputs", "validation", "poiseuille.yaml")
    out_dir = os.path.join(work, "out")
    args = ["--set", "output.every_steps=10", "--set", "output.progress_every=100000", "-q"]
    code, out, err, _ = run(["run", case, "-o", out_dir, "--steps", "40",
                             "--checkpoint-every", "20", *args])
    expect(code == 0, f"the run that writes checkpoints: exit {code} {err.strip()}")

    def listing():
        return sorted(os.listdir(out_dir)) + sorted(os.listdir(os.path.join(out_dir, "checkpoints")))

    before = listing()
    ckpt = sorted(glob.glob(os.path.join(out_dir, "checkpoints", "*.ckpt.h5")))[-1]
    pristine = os.path.join(work, "pristine.h5")
    shutil.copy(ckpt, pristine)
    expect(len(glob.glob(os.path.join(out_dir, "*.h5"))) >= 4 and ckpt.endswith("00000040.ckpt.h5"),
           f"snapshots and checkpoints written: {before}")

    # A refused restart deletes nothing; it removes a stale temporary.
    for name, value, message in [("step", -5, "attribute 'step' is -5, outside [0,"),
                                 ("step", 30, "named for step 40, its attribute 'step' is 30")]:
        shutil.copy(pristine, ckpt)
        with h5py.File(ckpt, "r+") as f:
            f.attrs.modify(name, value)
        stale = os.path.join(out_dir, "checkpoints", ".poiseuille_00000060.ckpt.h5.tmp")
        open(stale, "w").write("a write that never finished")
        code, o, err, _ = run(["run", case, "-o", out_dir, "--steps", "60", "--restart", ckpt,
                               *args])
        expect(code == 2 and message in err, f"{name} = {value}: exit {code}: {err.strip()[-250:]}")
        expect(listing() == before, f"{name} = {value}: nothing deleted: {listing()}")
        expect(not os.path.exists(stale), "the stale checkpoint temporary is removed")
    for name, value, message in [
            ("time", float("nan"), "attribute 'time' is nan, not a finite number"),
            ("time", 1e300, "more than 1e+09 output intervals"),
            ("time", -1.0, "attribute 'time' is -1, outside [0,"),
            ("dt", 0.0, "attribute 'dt' is 0, outside (0,"),
            ("dt", float("inf"), "attribute 'dt' is inf"),
            ("dt_limit", 99, "attribute 'dt_limit' is 99"),
            ("snapshots", -1, "attribute 'snapshots' is -1"),
            ("last_snapshot_step", 41, "attribute 'last_snapshot_step' is 41"),
            ("repartitions", -3, "attribute 'repartitions' is -3")]:
        shutil.copy(pristine, ckpt)
        with h5py.File(ckpt, "r+") as f:
            f.attrs.modify(name, value)
        code, o, err, _ = run(["run", case, "-o", out_dir, "--steps", "60", "--restart", ckpt,
                               *args])
        expect(code == 2 and message in err, f"{name} = {value}: exit {code}: {err.strip()[-250:]}")
        expect(listing() == before, f"{name} = {value}: nothing deleted")
    shutil.copy(pristine, ckpt)
    with h5py.File(ckpt, "r+") as f:
        f["sph"].attrs.modify("count", -7)
    code, o, err, _ = run(["run", case, "-o", out_dir, "--steps", "60", "--restart", ckpt, *args])
    expect(code == 2 and "count of -7" in err, f"sph count -7: exit {code}: {err.strip()[-250:]}")
    expect(listing() == before, "sph count -7: nothing deleted")
    # The pristine checkpoint still restarts.
    shutil.copy(pristine, ckpt)
    code, o, err, _ = run(["run", case, "-o", out_dir, "--steps", "60", "--restart", ckpt, *args])
    expect(code == 0, f"the unedited checkpoint restarts: exit {code} {err.strip()[-200:]}")

else:
    print("unknown scenario " + scenario)
    sys.exit(2)

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
