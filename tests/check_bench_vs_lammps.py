#!/usr/bin/env python3
"""tools/bench_vs_lammps.sh (issue 19, docs/performance.md "Against the
peer, side by side") without the real codes: no timings are taken here.

  - --help exits 0 and names the options; a bad option or value exits 2;
  - --dry-run --build-peer with no LAMMPS prints the Debian source build
    (apt-get source lammps with a private apt directory, the cmake build
    with the SPH package) and the hyperfine rounds, and runs nothing;
  - a full run with stand-ins for bench_sph and lmp (shell scripts that log
    their arguments) alternates sphdem, LAMMPS continuity, LAMMPS summation
    in every round, passes --set on to sphdem, and prints one table row per
    case and rank count with a median and range per ratio;
  - the DEM decks (bpm4800 with a bench_dem stand-in) alternate with the
    BPM deck and print a row per rank count and sphdem's speed-up;
  - sphdem runs with the shipped cases' delta-SPH unless --bare;
  - --pin CPUS runs both codes under taskset (the stand-ins see only CPUS),
    and a --pin that is not a CPU list exits 2;
  - a mirror without the .dsc (apt-get source fails after downloading the
    tarballs, stand-ins for apt-get and cmake): the tarballs are unpacked,
    Debian's patch series applied, and the peer built from that source.

usage: check_bench_vs_lammps.py SOURCE_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys

if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)
src, work = sys.argv[1], os.path.abspath(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
script = os.path.join(src, "tools", "bench_vs_lammps.sh")
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(*args, env=None):
    e = dict(os.environ)
    e.pop("LMP", None)
    e["PATH"] = "/usr/bin:/bin"  # no lmp on PATH
    e.update(env or {})
    return subprocess.run(["bash", script, *args], capture_output=True, text=True, env=e)


r = run("--help")
expect(r.returncode == 0 and all(o in r.stdout for o in
       ("--cases", "--ranks", "--rounds", "--build-peer", "--dry-run", "--lmp")),
       "--help exits 0 and names the options")
r = run("--frobnicate")
expect(r.returncode == 2 and "--frobnicate" in r.stderr, "an unknown option exits 2 naming it")
r = run("--rounds", "0")
expect(r.returncode == 2 and "--rounds" in r.stderr, "--rounds 0 exits 2 naming the option")
r = run("--ranks", "two")
expect(r.returncode == 2 and "--ranks" in r.stderr, "--ranks two exits 2 naming the option")

# A peer directory of its own: a peer already built in the source tree's
# build/peers/lammps would be found and nothing would be built.
peer_dir = os.path.join(work, "no-peer")
shutil.rmtree(peer_dir, ignore_errors=True)
had_peer_dir = False
r = run("--dry-run", "--build-peer", "--cases", "21k 99k", "--ranks", "1 2", "--rounds", "2",
        "--peer-dir", peer_dir,
        "--out", os.path.join(work, "dry"), "--lmp", os.path.join(work, "no-such-lmp"))
out = r.stdout.replace("\\ ", " ")  # printf %q escapes the spaces
expect(r.returncode == 0, "--dry-run --build-peer exits 0")
expect("source lammps" in out and "trixie" in out, "the dry run shows apt-get source lammps (trixie)")
expect("PKG_SPH=yes" in out and "PKG_BPM=yes" in out, "the dry run shows the peer build with SPH, BPM")
expect(out.count("+ hyperfine") == 2 * 2 * 2, "two rounds per case and rank count")
expect("--nx 720 --ny 132" in out and "nx 720 -var ny 132" in out, "the 99k channel for both codes")
expect("-n 2" in out, "the 2-rank runs")
expect(not os.path.exists(os.path.join(work, "dry")), "the dry run creates nothing")
expect(had_peer_dir or not os.path.exists(peer_dir), "the dry run builds nothing")


def stand_ins(prefix, log, what):
    """bench_sph and lmp stand-ins that append "sphdem WHAT" or "lammps WHAT"
    to log (WHAT a shell word); lmp answers -h with its packages."""
    bench, lmp = os.path.join(work, prefix + "bench_sph"), os.path.join(work, prefix + "lmp")
    with open(bench, "w") as f:
        f.write(f'#!/bin/sh\necho "sphdem {what}" >> {log}\n')
    with open(lmp, "w") as f:
        f.write(f'#!/bin/sh\nif [ "$1" = -h ]; then printf "Installed packages:\\n\\nBPM GRANULAR SPH\\n"; '
                f'exit 0; fi\necho "lammps {what}" >> {log}\n')
    os.chmod(bench, 0o755)
    os.chmod(lmp, 0o755)
    return bench, lmp


# Stand-ins that log their arguments.
log = os.path.join(work, "calls.log")
fake_bench, fake_lmp = stand_ins("", log, "$*")
r = run("--cases", "21k", "--ranks", "1", "--rounds", "2", "--steps", "10", "--bench", fake_bench,
        "--set", "numerics.delta_sph=0.1", "--out", os.path.join(work, "real"),
        env={"LMP": fake_lmp, "PATH": "/usr/bin:/bin"})
print(r.stdout, r.stderr)
expect(r.returncode == 0, "a run with stand-ins exits 0")
calls = open(log).read().splitlines() if os.path.exists(log) else []
order = ["sphdem" if c.startswith("sphdem") else ("cont" if "dens cont" in c else "sum") for c in calls]
expect(order == ["sphdem", "cont", "sum"] * 2, f"alternating rounds: {order}")
expect(all("--set numerics.delta_sph=0.1" in c for c in calls if c.startswith("sphdem")),
       "--set reaches sphdem")
expect(all("-var nsteps 10" in c for c in calls if c.startswith("lammps")), "--steps reaches the peer")
row = re.search(r"^\| 21k \| 1 \| 2 \|( [0-9.]+ \([0-9.]+-[0-9.]+\) \|){3}$", r.stdout, re.M)
expect(row is not None, "one table row: median (min-max) of three ratios")

# --startup: each round also runs the three commands with 0 steps, after
# the others, and a table gives the 0-step times and the steps-alone ratio
# (the stand-ins' times are noise: that ratio may come out negative here).
open(log, "w").close()
r = run("--cases", "21k", "--ranks", "1", "--rounds", "2", "--steps", "10", "--bench", fake_bench,
        "--startup", "--out", os.path.join(work, "startup"),
        env={"LMP": fake_lmp, "PATH": "/usr/bin:/bin"})
print(r.stdout, r.stderr)
calls = open(log).read().splitlines()
kinds = [("sphdem" if c.startswith("sphdem") else ("cont" if "dens cont" in c else "sum")) +
         ("0" if ("--steps 0" in c or "-var nsteps 0" in c) else "") for c in calls]
expect(r.returncode == 0 and kinds == ["sphdem", "cont", "sum", "sphdem0", "cont0", "sum0"] * 2,
       f"--startup: 0-step runs in every round, after the others: {kinds}")
expect(re.search(r"^\| 21k \| 1 \| [0-9.]+ \([0-9.]+-[0-9.]+\) \| [0-9.]+ \([0-9.]+-[0-9.]+\) \| "
                 r"(-?[0-9.]+ \(-?[0-9.]+--?[0-9.]+\)|-) \|$", r.stdout, re.M) is not None,
       "--startup: a row of 0-step times and the steps-alone ratio")

# --pin: every run of both codes on the given CPUs (the stand-ins log the
# CPUs the kernel lets them run on).
pin_log = os.path.join(work, "pin.log")
pin_bench, pin_lmp = stand_ins("pin_", pin_log, "$(grep Cpus_allowed_list /proc/$$/status | cut -f2)")
r = run("--cases", "21k", "--ranks", "1", "--rounds", "1", "--steps", "10", "--bench", pin_bench,
        "--pin", "0", "--out", os.path.join(work, "pin"), env={"LMP": pin_lmp, "PATH": "/usr/bin:/bin"})
print(r.stdout, r.stderr)
pins = open(pin_log).read().splitlines() if os.path.exists(pin_log) else []
expect(r.returncode == 0 and len(pins) == 3 and all(p.split()[1] == "0" for p in pins),
       f"--pin 0 runs sphdem and both peer modes on CPU 0: {pins}")
r = run("--pin", "one", "--dry-run", "--lmp", fake_lmp)
expect(r.returncode == 2 and "--pin" in r.stderr, "--pin one exits 2 naming the option")

# The DEM decks: bench_dem against the BPM deck, alternating, at two rank
# counts, with sphdem's speed-up between them.
fake_dem = os.path.join(work, "bench_dem")
with open(fake_dem, "w") as f:
    f.write(f'#!/bin/sh\necho "sphdem_dem $*" >> {log}\n')
os.chmod(fake_dem, 0o755)
open(log, "w").close()
r = run("--cases", "bpm4800", "--ranks", "1 2", "--rounds", "2", "--dem-steps", "30",
        "--bench-dem", fake_dem, "--out", os.path.join(work, "dem"),
        env={"LMP": fake_lmp, "PATH": "/usr/bin:/bin"})
print(r.stdout, r.stderr)
expect(r.returncode == 0, "a DEM run with stand-ins exits 0")
calls = open(log).read().splitlines()
order = ["sphdem" if c.startswith("sphdem_dem") else "bpm" for c in calls]
# mpirun -n 2 starts each stand-in twice; each round runs every rank count,
# so the speed-up compares runs of the same minutes
expect(order == (["sphdem", "bpm"] + ["sphdem", "sphdem", "bpm", "bpm"]) * 2,
       f"DEM rounds alternate, rank counts within each round: {order}")
expect(all("--dim 3 --fibers 4800 --steps 30" in c for c in calls if c.startswith("sphdem")),
       "bench_dem gets the deck's fibers and --dem-steps")
expect(all("-in in.bpm_fibers_3d -var nfx 20 -var nfy 20 -var nfz 12 -var nsteps 30" in c
           for c in calls if c.startswith("lammps")), "the BPM deck gets the 4800 lattice")
expect(re.search(r"^\| bpm4800 \| 2 \| 2 \| [0-9.]+ \([0-9.]+-[0-9.]+\) \|$", r.stdout, re.M)
       is not None, "one DEM table row per rank count")
expect(re.search(r"^\| bpm4800 \| 2: [0-9.]+ \([0-9.]+-[0-9.]+\) \|$", r.stdout, re.M) is not None,
       "sphdem's speed-up from 1 to 2 ranks")
r = run("--cases", "21k bpm9", "--dry-run", "--lmp", fake_lmp)
expect(r.returncode == 2 and "bpm9" in r.stderr, "an unknown case exits 2 naming it")
r = run("--dem-steps", "-3")
expect(r.returncode == 2 and "--dem-steps" in r.stderr, "--dem-steps -3 exits 2 naming the option")

# The shipped cases' physics by default (delta-SPH), none with --bare.
r = run("--dry-run", "--cases", "21k", "--ranks", "1", "--rounds", "1", "--lmp", fake_lmp)
expect(r.returncode == 0 and "--set numerics.delta_sph=0.1" in r.stdout.replace("\\ ", " "),
       "sphdem runs with delta-SPH by default")
r = run("--dry-run", "--bare", "--cases", "21k", "--ranks", "1", "--rounds", "1", "--lmp", fake_lmp)
expect(r.returncode == 0 and "delta_sph" not in r.stdout, "--bare drops the default overrides")

# A mirror that serves the tarballs but not the .dsc: apt-get source fails
# after the download; the script unpacks the tarballs, applies the patch
# series and builds from there. Stand-ins for apt-get and cmake.
fakebin = os.path.join(work, "fakebin")
stage = os.path.join(work, "stage")
os.makedirs(os.path.join(stage, "up", "lammps-4Feb2025", "cmake"))
os.makedirs(os.path.join(stage, "deb", "debian", "patches"))
with open(os.path.join(stage, "up", "lammps-4Feb2025", "cmake", "version.txt"), "w") as f:
    f.write("upstream\n")
with open(os.path.join(stage, "deb", "debian", "patches", "series"), "w") as f:
    f.write("# Debian's patches\nfix.patch\n")
with open(os.path.join(stage, "deb", "debian", "patches", "fix.patch"), "w") as f:
    f.write("--- a/cmake/version.txt\n+++ b/cmake/version.txt\n@@ -1 +1 @@\n-upstream\n+patched\n")
subprocess.run(["tar", "-cJf", os.path.join(stage, "lammps_20250204+dfsg.1.orig.tar.xz"), "-C",
                os.path.join(stage, "up"), "lammps-4Feb2025"], check=True)
subprocess.run(["tar", "-cJf", os.path.join(stage, "lammps_20250204+dfsg.1-2.debian.tar.xz"), "-C",
                os.path.join(stage, "deb"), "debian"], check=True)
os.makedirs(fakebin)
with open(os.path.join(fakebin, "apt-get"), "w") as f:
    f.write(f'#!/bin/sh\ncase "$*" in *" source lammps") cp {stage}/lammps_*.tar.xz . ; '
            f'echo "E: Failed to fetch lammps_20250204+dfsg.1-2.dsc  404  Not Found" >&2; exit 100 ;; '
            f'esac\nexit 0\n')
with open(os.path.join(fakebin, "cmake"), "w") as f:
    f.write(f'#!/bin/sh\necho "cmake $*" >> {log}\nif [ "$1" = --build ]; then '
            f'cp {fake_lmp} "$2/lmp"; else mkdir -p "$4"; fi\n')
for b in ("apt-get", "cmake"):
    os.chmod(os.path.join(fakebin, b), 0o755)
open(log, "w").close()
peer = os.path.join(work, "peer")
r = run("--build-peer", "--peer-dir", peer, "--cases", "21k", "--ranks", "1", "--rounds", "1",
        "--steps", "10", "--bench", fake_bench, "--out", os.path.join(work, "built"),
        env={"PATH": fakebin + ":/usr/bin:/bin"})
print(r.stdout, r.stderr)
unpacked = os.path.join(peer, "lammps-20250204+dfsg.1")
version = os.path.join(unpacked, "cmake", "version.txt")
expect(r.returncode == 0, "a build from the downloaded tarballs exits 0")
expect(os.path.exists(version) and open(version).read() == "patched\n",
       "the upstream tarball is unpacked and Debian's patch series applied")
calls = open(log).read().splitlines()
expect(any(c.startswith(f"cmake -S {unpacked}/cmake") and "PKG_SPH=yes" in c for c in calls),
       "the peer is configured from the unpacked source with the SPH package")
expect(any(c.startswith("lammps") for c in calls), "the comparison then runs the built peer")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("all passed")
