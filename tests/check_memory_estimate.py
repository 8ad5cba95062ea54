#!/usr/bin/env python3
"""`sphdem check --ranks P [--memory-per-rank M]` (issue 14 part 4,
docs/scaling.md, "Memory per rank"): the peak memory per rank estimated
for P ranks before anything is built.

  - the plate at spacing 1e-6 m (9e8 particles) on 16 ranks with 4G per
    rank is refused, exit 2, naming the rank count, the estimate and the
    key, without building anything (the answer comes from the geometry
    alone); on 4096 ranks it fits, since the set-up is distributed (issue
    14 part 1: each rank builds only its share);
  - the plate on 4 ranks with 8G per rank fits: exit 0, the estimate for 4
    ranks, nothing built; with 1M per rank it is refused naming 4 ranks;
  - on 1 rank the estimate is larger than on 4 (the share);
  - bad values (--memory-per-rank lots, --ranks 0) exit 2 naming the option.

usage: check_memory_estimate.py SPHDEM SOURCE_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) != 4 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)

exe, src, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
plate = os.path.join(src, "inputs", "plate.yaml")
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(*args):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run([exe, "check", plate, *args], capture_output=True, cwd=work,
                       timeout=scaled(120), env=env)
    return p.returncode, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace")


def per_rank_bytes(text):
    """The estimate of `memory: about X per rank` or `needs about X per rank`."""
    m = re.search(r"about ([0-9.e+]+) (MiB|GiB|TiB) per rank", text)
    return float(m.group(1)) * 1024.0 ** {"MiB": 2, "GiB": 3, "TiB": 4}[m.group(2)] if m else None


fine = ["--set", "numerics.spacing=1e-6"]
code, out, err = run(*fine, "--ranks", "16", "--memory-per-rank", "4G")
expect(code == 2 and "per rank at 16 rank(s)" in err and "of --memory-per-rank" in err and
       "key 'numerics.spacing'" in err and "the peak is while running" in err,
       f"spacing 1e-6 on 16 ranks refused: exit {code}, {err.strip()}")
huge = per_rank_bytes(err)
expect(huge is not None and huge > 4 * 1024.0 ** 3, f"the estimate is above 4G: {huge}")
expect("is valid" not in out, "nothing was built")
code, out, err = run(*fine, "--ranks", "4096", "--memory-per-rank", "4G")
spread = per_rank_bytes(out)
expect(code == 0 and "per rank at 4096 rank(s)" in out and spread is not None and
       spread < 4 * 1024.0 ** 3,
       f"spacing 1e-6 fits 4G per rank on 4096 ranks (each builds its share): exit {code}, "
       f"{out}{err}")

code, out, err = run("--ranks", "4", "--memory-per-rank", "8G")
expect(code == 0 and "estimated for 4 ranks, not built" in out and
       "per rank at 4 rank(s)" in out, f"the plate fits 4 ranks: exit {code}, {out}{err}")
four = per_rank_bytes(out)
code, out, err = run("--ranks", "1", "--memory-per-rank", "8G")
one = per_rank_bytes(out)
expect(code == 0 and one and four and one > four, f"1 rank needs more than 4: {one} > {four}")

code, out, err = run("--ranks", "4", "--memory-per-rank", "1M")
expect(code == 2 and "per rank at 4 rank(s)" in err and "more than the" in err,
       f"1M per rank refuses the plate on 4 ranks: exit {code}, {err.strip()}")

code, out, err = run("--ranks", "4", "--memory-per-rank", "lots")
expect(code == 2 and "--memory-per-rank" in err, f"--memory-per-rank lots: {err.strip()}")
code, out, err = run("--ranks", "0")
expect(code == 2 and "--ranks" in err, f"--ranks 0: exit {code}, {err.strip()}")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
