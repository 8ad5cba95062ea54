#!/usr/bin/env python3
"""Peak memory per rank and read time of a restart of a case with many fibers
(docs/checkpoint.md "At scale", docs/scaling.md "Restart").

The fibers-only bath (inputs/fibers_only.yaml) enlarged to a square of side
--side (m) with --fibers fibers of 4 particles: sphdem writes a checkpoint
at step 2 on one rank, then for each rank count P of --ranks it measures,
each rank wrapped in `/usr/bin/time -v`:

  set-up    `sphdem run --steps 0`: placing the fibers and the first
            snapshot (each rank places the fibers of its tiles'
            neighbourhood: docs/dem.md "Fiber generator");
  restart   `sphdem run --restart <checkpoint> --steps 2`: the set-up, then
            the checkpoint read, the migration to the owners, the first
            rebuild and a snapshot.

It prints, per P and phase, the largest and the mean peak resident set size
over the ranks (MiB) and, for the restart, the time sphdem reports for it
("read in ... s", rank 0's clock). The restart's own cost is the difference
between the two phases. Run it with the sphdem of each version to compare.

usage: restart_memory.py [-h] [--sphdem PATH] [--mpiexec CMD] [--ranks P ...]
                         [--fibers N] [--side L] [--work DIR]

example (from the project root):
  python3 tools/restart_memory.py --sphdem build/release/sphdem --ranks 1 4 \\
      --fibers 40000 --side 0.3 --work out/restart_memory
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PEAK = re.compile(r"Maximum resident set size \(kbytes\): (\d+)")
READ = re.compile(r"read in ([0-9.eE+-]+) s")


def case_overrides(fibers, side):
    """--set arguments: the bath and its fibers in a square of side `side`."""
    lo_y, hi_y, half = 0.030, 0.030 + side, side / 2
    box = "[%r,%r]"
    return ["--set", "mold.shapes[0].box.min=" + box % (-half, lo_y),
            "--set", "mold.shapes[0].box.max=" + box % (half, hi_y),
            "--set", "fibers.region.box.min=" + box % (-half, lo_y),
            "--set", "fibers.region.box.max=" + box % (half, hi_y),
            "--set", "moving_walls[0].region.box.min=" + box % (-half, hi_y),
            "--set", "moving_walls[0].region.box.max=" + box % (half, hi_y + 0.0015),
            "--set", "fibers.count=%d" % fibers]


def run(cmd):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit("restart_memory.py: %s failed (exit %d):\n%s" %
                 (" ".join(cmd), p.returncode, (p.stdout + p.stderr)[-2000:]))
    return p.stdout, p.stderr


def measured(mpiexec, ranks, sphdem, args):
    """Peak RSS of every rank (MiB) and sphdem's output of one run."""
    cmd = mpiexec.split() + ["-n", str(ranks), "--oversubscribe", "/usr/bin/time", "-v",
                             sphdem] + args
    out, err = run(cmd)
    peaks = [int(k) / 1024.0 for k in PEAK.findall(err)]
    if len(peaks) != ranks:
        sys.exit("restart_memory.py: expected %d peaks from /usr/bin/time, got %d" %
                 (ranks, len(peaks)))
    return peaks, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--sphdem", default=os.path.join(ROOT, "build", "release", "sphdem"),
                    help="the sphdem binary (default build/release/sphdem)")
    ap.add_argument("--mpiexec", default="mpiexec", help="MPI launcher (default mpiexec)")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 4], help="rank counts (1 4)")
    ap.add_argument("--fibers", type=int, default=40000, help="fibers of 4 particles (40000)")
    ap.add_argument("--side", type=float, default=0.3, help="side of the bath [m] (0.3)")
    ap.add_argument("--work", default=os.path.join("out", "restart_memory"),
                    help="work directory, emptied first (out/restart_memory)")
    a = ap.parse_args()
    if not os.path.exists(a.sphdem):
        sys.exit("restart_memory.py: no sphdem binary at '%s'" % a.sphdem)
    if not os.path.exists("/usr/bin/time"):
        sys.exit("restart_memory.py: needs /usr/bin/time (Debian package time)")
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    case = os.path.join(ROOT, "inputs", "fibers_only.yaml")
    sets = case_overrides(a.fibers, a.side)
    ckpt_dir = os.path.join(a.work, "checkpoint")
    run([a.sphdem, "run", case, "-o", ckpt_dir, "--steps", "2", "--checkpoint-every", "2", "-q"]
        + sets)
    ckpt = os.path.join(ckpt_dir, "checkpoints", "fibers_only_00000002.ckpt.h5")
    size = os.path.getsize(ckpt) / 2**20
    print("case: %d fibers (%d DEM particles) in a %.3g m bath; checkpoint %.1f MiB" %
          (a.fibers, 4 * a.fibers, a.side, size))
    print("%5s  %-8s %12s %12s %10s" % ("ranks", "phase", "max MiB", "mean MiB", "read s"))
    for p in a.ranks:
        setup, _ = measured(a.mpiexec, p, a.sphdem, ["run", case, "-o",
                                                     os.path.join(a.work, "setup_np%d" % p),
                                                     "--steps", "0", "-q"] + sets)
        restart, out = measured(a.mpiexec, p, a.sphdem,
                                ["run", case, "-o", os.path.join(a.work, "restart_np%d" % p),
                                 "--restart", ckpt, "--steps", "2"] + sets)
        read = READ.search(out)
        for phase, peaks, secs in (("set-up", setup, "-"),
                                   ("restart", restart, read.group(1) if read else "?")):
            print("%5d  %-8s %12.1f %12.1f %10s" % (p, phase, max(peaks), sum(peaks) / p, secs),
                  flush=True)


if __name__ == "__main__":
    main()
