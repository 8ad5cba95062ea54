#!/usr/bin/env python3
"""`sphdem scaling` end to end (docs/scaling.md, "Scaling studies of any case"):
a two-point strong and weak study (1 and 2 ranks, a few steps) of the small
coupled case inputs/validation/coupled_box.yaml, the CSV's columns, weak
scaling's particles per rank within 5 % and doubled fibers, the plot of
tools/plot_scaling.py, and bad input that exits 2 before anything runs.

usage: check_scaling.py SPHDEM_BINARY SOURCE_DIR WORK_DIR "MPIEXEC FLAGS"
"""
import csv
import os
import shutil
import subprocess
import sys

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) != 5 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)

exe, src, work, mpiexec = sys.argv[1:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
case = os.path.join(src, "inputs", "validation", "coupled_box.yaml")
launcher = mpiexec + " -n {n}"
failures = []

PHASES = ["compute", "halo", "migration", "rebalance", "io", "wait", "dem", "coupling"]
COLUMNS = (["mode", "ranks", "spacing", "resin", "wall", "fibers", "dem", "particles",
            "moving_per_rank", "steps", "wall_s", "particle_steps_per_s", "efficiency"] +
           [p + s for p in PHASES for s in ("_max", "_mean")] +
           ["step_lag_max", "imbalance_max", "run", "repeats"])


def run(*args):
    p = subprocess.run([exe, "scaling", *args], capture_output=True, text=True, cwd=work,
                       timeout=scaled(600))
    return p.returncode, p.stdout, p.stderr


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def study(name, *extra):
    code, out, err = run(case, "--ranks", "1,2", "--steps", "4", "--launcher", launcher,
                         "-o", name, *extra)
    expect(code == 0, "%s study exits 0: %s %s" % (name, out[-2000:], err[-2000:]))
    path = os.path.join(work, name, "scaling.csv")
    if code != 0 or not os.path.exists(path):
        return []
    with open(path) as f:
        reader = csv.DictReader(f)
        expect(reader.fieldnames == COLUMNS, "%s CSV columns: %s" % (name, reader.fieldnames))
        rows = list(reader)
    expect([int(r["ranks"]) for r in rows] == [1, 2], "%s: one row per rank count" % name)
    for r in rows:
        expect(int(r["steps"]) == 4 and float(r["wall_s"]) > 0 and
               float(r["particle_steps_per_s"]) > 0, "%s %s ranks: steps, time, rate" %
               (name, r["ranks"]))
        expect(all(float(r[p + "_max"]) >= float(r[p + "_mean"]) >= 0 for p in PHASES),
               "%s %s ranks: phase max >= mean >= 0" % (name, r["ranks"]))
        expect(float(r["compute_max"]) > 0 and float(r["dem_max"]) > 0 and
               float(r["coupling_max"]) > 0, "%s %s ranks: compute, dem, coupling timed" %
               (name, r["ranks"]))
        # docs/parallel.md, "Per-step times": the lag behind each step's
        # slowest rank is at least the totals' imbalance; both 0 on 1 rank.
        lag, imbalance = float(r["step_lag_max"]), float(r["imbalance_max"])
        expect(lag + 1e-6 >= imbalance >= 0 and (r["ranks"] != "1" or lag == imbalance == 0),
               "%s %s ranks: step lag %g >= imbalance %g" % (name, r["ranks"], lag, imbalance))
        total = sum(float(r[p + "_max"]) for p in PHASES)
        expect(total >= float(r["wall_s"]) * 0.999,
               "%s %s ranks: the phases' maxima cover the wall time" % (name, r["ranks"]))
    expect(abs(float(rows[0]["efficiency"]) - 1) < 1e-9, "%s: efficiency 1 at 1 rank" % name)
    # Efficiency = particle-steps/s per rank relative to the first row.
    rate = [float(r["particle_steps_per_s"]) / int(r["ranks"]) for r in rows]
    expect(abs(float(rows[1]["efficiency"]) - rate[1] / rate[0]) < 1e-3,
           "%s: efficiency from particle-steps/s per rank" % name)
    with open(os.path.join(work, name, "scaling_all_runs.csv")) as f:
        expect(len(list(csv.DictReader(f))) == 2 * int(rows[0]["repeats"]),
               "%s: every run in scaling_all_runs.csv" % name)
    return rows


strong = study("strong", "--repeat", "2")
if strong:
    expect(strong[0]["particles"] == strong[1]["particles"] and
           strong[0]["spacing"] == strong[1]["spacing"], "strong: the same case on 1 and 2 ranks")
    expect(all(r["repeats"] == "2" and r["run"] in ("1", "2") for r in strong),
           "strong: the kept run of 2 repeats")

weak = study("weak", "--weak")
if weak:
    per_rank = [float(r["moving_per_rank"]) for r in weak]
    expect(abs(per_rank[1] / per_rank[0] - 1) < 0.05,
           "weak: resin + fiber particles per rank within 5 %%: %s" % per_rank)
    expect(int(weak[1]["fibers"]) == 2 * int(weak[0]["fibers"]), "weak: twice the fibers")
    expect(abs(float(weak[0]["spacing"]) / float(weak[1]["spacing"]) - 2 ** 0.5) < 1e-6,
           "weak: spacing / sqrt(2) on 2 ranks")

    # The plot of the study (tools/plot_scaling.py): efficiency and phases.
    png = os.path.join(work, "weak.png")
    p = subprocess.run([sys.executable, os.path.join(src, "tools", "plot_scaling.py"),
                        os.path.join(work, "weak", "scaling.csv"), "-o", png],
                       capture_output=True, text=True, timeout=scaled(120))
    expect(p.returncode == 0 and os.path.getsize(png) > 1000,
           "plot_scaling.py draws the study: " + p.stdout + p.stderr)


# The cluster scripts, with stand-ins for sbatch/srun and qsub that run each
# job at once on this machine (the rank count's allocation from the job's
# header: SLURM_NTASKS, PBS_NODEFILE).
fake = os.path.join(work, "fake_bin")
os.makedirs(fake)


def script(name, text):
    path = os.path.join(fake, name)
    with open(path, "w") as f:
        f.write("#!/bin/bash\nset -euo pipefail\n" + text)
    os.chmod(path, 0o755)


script("sbatch", """job=${@: -1}
n=$(sed -n 's/^#SBATCH --ntasks=//p' "$job")
SLURM_NTASKS=$n bash "$job" >> "$job.ran" 2>&1
echo "$RANDOM"
""")
script("srun", 'exec %s "$@"\n' % mpiexec)
script("qsub", """job=${@: -1}
chunks=$(sed -n 's/^#PBS -l select=\\([0-9]*\\):.*/\\1/p' "$job")
procs=$(sed -n 's/^#PBS -l select=.*mpiprocs=\\([0-9]*\\).*/\\1/p' "$job")
nodes=$(mktemp); for _ in $(seq $((chunks * ${procs:-1}))); do echo localhost; done > "$nodes"
PBS_NODEFILE=$nodes bash "$job" >> "$job.ran" 2>&1
rm -f "$nodes"
echo "$RANDOM.server"
""")
env = dict(os.environ, PATH=fake + os.pathsep + os.environ["PATH"], SPHDEM=exe,
           OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
for name in ("slurm", "pbs"):
    out_dir = os.path.join(work, name)
    p = subprocess.run([os.path.join(src, "jobscripts", "scaling_%s.sh" % name), case, out_dir,
                        "1,2", "3", "--weak"], capture_output=True, text=True, env=env, cwd=work,
                       timeout=scaled(600))
    rows = []
    if os.path.exists(os.path.join(out_dir, "scaling.csv")):
        rows = list(csv.DictReader(open(os.path.join(out_dir, "scaling.csv"))))
    expect(p.returncode == 0 and [r["ranks"] for r in rows] == ["1", "2"] and
           all(r["mode"] == "weak" and r["steps"] == "3" for r in rows),
           "jobscripts/scaling_%s.sh: one job per rank count, rows collected: %s %s" %
           (name, p.stdout, p.stderr))
p = subprocess.run([os.path.join(src, "jobscripts", "scaling_slurm.sh"), case,
                    os.path.join(work, "slurm_bad"), "2,1", "3"], capture_output=True, text=True,
                   env=env, cwd=work, timeout=scaled(60))
expect(p.returncode == 2 and "increasing" in p.stderr and
       not os.path.exists(os.path.join(work, "slurm_bad", "jobs")),
       "scaling_slurm.sh: bad rank list, nothing submitted: " + p.stderr.strip())

# Bad input: exit 2 with a message naming the option, nothing run or written.
bad = [
    (["--ranks", "", "--launcher", launcher], "--ranks: the rank list is empty"),
    (["--ranks", "2,1", "--launcher", launcher], "must be increasing"),
    (["--ranks", "1,1", "--launcher", launcher], "must be increasing"),
    (["--ranks", "1,x", "--launcher", launcher], "not a positive integer"),
    (["--ranks", "1,4", "--slots", "2", "--launcher", "mpiexec -n {n}"],
     "4 ranks, but the launcher can start 2"),
    (["--ranks", "1,2", "--launcher", "mpiexec -n 2"], "has no {n}"),
    (["--ranks", "1,1000000", "--weak", "--launcher", launcher], "needs about"),
    (["--ranks", "1,2", "--weak", "--memory-gb", "0.0001", "--launcher", launcher],
     "more than the 0.0001 GB available"),
    (["--ranks", "1,2", "--repeat", "0", "--launcher", launcher], "--repeat: must be >= 1"),
]
for args, message in bad:
    code, out, err = run(case, "--steps", "2", "-o", "bad", *args)
    expect(code == 2 and message in err and not os.path.exists(os.path.join(work, "bad")),
           "%s exits 2 (%s), nothing written: %s" % (" ".join(args), message, err.strip()))
pois = os.path.join(src, "inputs", "validation", "poiseuille.yaml")
code, out, err = run(pois, "--ranks", "1,2", "--weak", "--steps", "2", "-o", "bad",
                     "--launcher", launcher)
expect(code == 2 and "periodic length" in err and "squares (e.g. 1,4,16)" in err, "weak periodic case at 2 ranks: " + err.strip())
code, out, err = run("--help")
expect(code == 0 and "--weak" in out and "--launcher" in out, "scaling --help")

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
