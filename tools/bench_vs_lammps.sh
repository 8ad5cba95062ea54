#!/usr/bin/env bash
# sphdem against its LAMMPS peer on the 2D channel and the BPM fiber decks (issue 19,
# docs/performance.md "Against the peer, side by side"): the two codes
# alternate in every round (hyperfine, one run of each command per round),
# so both see the same machine load, and the ratio of each round is what
# counts. Builds the peer from Debian's source package when it is missing.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DECK="$ROOT/bench/peers/lammps/in.sph_poiseuille_2d"
DEM_DECK_DIR="$ROOT/bench/peers/lammps"  # in.bpm_fibers_3d reads fiber4.mol from its directory
PEER_DIR="$ROOT/build/peers/lammps"
BENCH="$ROOT/build/release/bench/bench_sph"
BENCH_DEM="$ROOT/build/release/bench/bench_dem"
LMP="${LMP:-}"
CASES="21k 99k"
RANKS="1 2"
ROUNDS=5
STEPS=2000
DEM_STEPS=4000
OUT="$ROOT/out/bench_vs_lammps"
DRY=0
BUILD_PEER=0
STARTUP=0
PIN=""
# The shipped cases' physics (inputs/plate.yaml): bench_sph's channel has
# anti-clump and Morris viscosity on; delta-SPH is added here.
DEFAULT_SETS=("numerics.delta_sph=0.1")
SETS=()

usage() {
  cat <<EOF
usage: tools/bench_vs_lammps.sh [options]

Runs sphdem's channel benchmark (bench/bench_sph.cpp) and the LAMMPS deck
bench/peers/lammps/in.sph_poiseuille_2d (density by continuity and by
summation) alternating, one run of each per round, with hyperfine, and
prints per case and rank count the median and range over the rounds of
  sphdem wall time / LAMMPS wall time
for each peer density mode and for the faster of the two (whole process).
The DEM cases bpm175 and bpm4800 alternate bench/bench_dem.cpp (--dim 3)
with the BPM deck bench/peers/lammps/in.bpm_fibers_3d the same way and print
sphdem / LAMMPS BPM wall time; with more than one rank count, every case
also prints sphdem's speed-up from the first rank count to each other
(median and range of the per-round ratios of its wall times; each round
runs every rank count, so the ratio compares runs of the same minutes).
On a machine whose CPUs differ, pin (--pin) to see which CPU a 1-rank
run's time belongs to (docs/performance.md, "Issue 19's targets").
Quote only ratios measured this way: a figure divided by another day's
peer number is not comparable (bench/peers/lammps/README.md).

options:
  --cases "21k 99k"    channels: 21k = 320 x 60 (19,200 resin; with walls 20,480
                       in sphdem, 21,120 in the peer deck), 99k = 720 x 132
                       (95,040; 97,920 and 99,360); DEM decks: bpm175 (5 x 5 x 7
                       fibers of 4 spheres), bpm4800 (20 x 20 x 12) [$CASES]
  --ranks "1 2"        MPI rank counts                          [$RANKS]
  --rounds N           alternating rounds per case and rank count [$ROUNDS]
  --steps N            steps of both codes, channels            [$STEPS]
  --dem-steps N        sub-steps of both codes, DEM decks        [$DEM_STEPS]
  --set KEY=VALUE      a case-file override for sphdem (repeatable), added to
                       the defaults: ${DEFAULT_SETS[*]} (with bench_sph's
                       anti-clump and Morris viscosity, the physics of the
                       shipped cases, inputs/plate.yaml)
  --bare               drop the default overrides (the peer deck's physics
                       plus anti-clump, as measured before issue 19)
  --bench PATH         sphdem's bench_sph           [build/release/bench/bench_sph]
  --bench-dem PATH     sphdem's bench_dem           [build/release/bench/bench_dem]
  --lmp PATH           the LAMMPS executable (also \$LMP; else lmp on PATH,
                       else build/peers/lammps/build/lmp)
  --build-peer         if no LAMMPS with the SPH package is found, build one
                       from Debian 13's source package (upstream 4 Feb 2025;
                       Debian 12's binary package has no SPH/BPM): apt-get
                       source with a private apt directory (the system's
                       sources are not touched), then a Release MPI build with
                       SPH, GRANULAR, BPM, MOLECULE (about 10 min on 2 cores).
                       Needs dpkg-dev: scripts/install-deps.sh --peer
  --peer-dir DIR        where --build-peer downloads and builds  [build/peers/lammps]
  --out DIR            hyperfine's JSON per round              [out/bench_vs_lammps]
  --pin CPUS           run every command of both codes under taskset -c CPUS
                       (a list such as 1 or 0,1): on a machine whose CPUs are
                       not equal, 1-rank runs of both codes then land on the
                       same CPU (docs/performance.md, "this machine's two
                       CPUs"); use it with rank counts that fit in CPUS
  --startup            SPH cases: each round also runs both codes with 0 steps
                       (MPI start-up, set-up, the first lists, exit: what every
                       run pays once), alternating with the others, and prints
                       that fixed time per code and the ratio of the rest,
                       (sphdem - its 0-step time) / (faster peer - its 0-step
                       time): the steps alone
  --dry-run            print what would run (the peer build too), run nothing
  -h, --help           this help

Run it on a quiet machine: hyperfine's wall times are the measure.
EOF
}

while (($#)); do
  case "$1" in
    --cases) CASES="$2"; shift 2 ;;
    --ranks) RANKS="$2"; shift 2 ;;
    --rounds) ROUNDS="$2"; shift 2 ;;
    --steps) STEPS="$2"; shift 2 ;;
    --dem-steps) DEM_STEPS="$2"; shift 2 ;;
    --set) SETS+=("$2"); shift 2 ;;
    --bench) BENCH="$2"; shift 2 ;;
    --bench-dem) BENCH_DEM="$2"; shift 2 ;;
    --lmp) LMP="$2"; shift 2 ;;
    --build-peer) BUILD_PEER=1; shift ;;
    --bare) DEFAULT_SETS=(); shift ;;
    --out) OUT="$2"; shift 2 ;;
    --peer-dir) PEER_DIR="$2"; shift 2 ;;
    --pin) PIN="$2"; shift 2 ;;
    --startup) STARTUP=1; shift ;;
    --dry-run) DRY=1; shift ;;
    -h | --help) usage; exit 0 ;;
    *) echo "bench_vs_lammps: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
PEER_DIR=$(realpath -m "$PEER_DIR")  # run_in changes directory
[[ "$ROUNDS" =~ ^[1-9][0-9]*$ ]] || { echo "bench_vs_lammps: --rounds must be a positive integer, not '$ROUNDS'" >&2; exit 2; }
[[ "$STEPS" =~ ^[1-9][0-9]*$ ]] || { echo "bench_vs_lammps: --steps must be a positive integer, not '$STEPS'" >&2; exit 2; }
[[ "$DEM_STEPS" =~ ^[1-9][0-9]*$ ]] || { echo "bench_vs_lammps: --dem-steps must be a positive integer, not '$DEM_STEPS'" >&2; exit 2; }
SPH_CASES="" DEM_CASES=""
for c in $CASES; do
  case "$c" in
    21k | 99k) SPH_CASES+=" $c" ;;
    bpm175 | bpm4800) DEM_CASES+=" $c" ;;
    *) echo "bench_vs_lammps: unknown case '$c' in --cases (21k, 99k, bpm175 or bpm4800)" >&2; exit 2 ;;
  esac
done
for r in $RANKS; do
  [[ "$r" =~ ^[1-9][0-9]*$ ]] || { echo "bench_vs_lammps: --ranks takes positive integers, not '$r'" >&2; exit 2; }
done
[[ -z "$PIN" || "$PIN" =~ ^[0-9]+(-[0-9]+)?(,[0-9]+(-[0-9]+)?)*$ ]] || { echo "bench_vs_lammps: --pin takes a CPU list such as 1 or 0,1 or 0-3, not '$PIN'" >&2; exit 2; }

run() {  # prints the command; runs it unless --dry-run
  printf '+'
  printf ' %q' "$@"
  echo
  ((DRY)) || "$@"
}
run_in() {  # run, in directory $1
  local dir="$1"
  shift
  echo "+ (cd $dir && $*)"
  ((DRY)) || (cd "$dir" && "$@")
}

# A LAMMPS executable with the SPH package, or nothing.
# (grep reads all of -h: with -q it stops at the first match, lmp dies of SIGPIPE and
# pipefail turns a found package into "missing".)
has_sph() { [[ -x "$1" ]] && "$1" -h 2>/dev/null | grep -w SPH >/dev/null; }
find_peer() {
  local c
  for c in "$LMP" "$(command -v lmp 2>/dev/null || true)" "$PEER_DIR/build/lmp"; do
    [[ -n "$c" ]] && has_sph "$c" && { echo "$c"; return 0; }
  done
  return 1
}

build_peer() {
  local apt="$PEER_DIR/apt"
  local opts=(-o "Dir::Etc::SourceList=$apt/sources.list" -o "Dir::Etc::SourceParts=/nonexistent"
              -o "Dir::State::Lists=$apt/lists" -o "Dir::Cache=$apt/cache" -o "Debug::NoLocking=1")
  run mkdir -p "$apt/lists/partial" "$apt/cache/archives/partial"
  echo "+ write $apt/sources.list (Debian 13 'trixie' deb-src)"
  ((DRY)) || echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian trixie main" >"$apt/sources.list"
  run apt-get "${opts[@]}" update
  # Some mirrors serve the tarballs but not the .dsc; then apt-get source
  # fails after downloading them, and they are unpacked here the way
  # dpkg-source would (upstream tarball, debian/ tarball, its patch series).
  run_in "$PEER_DIR" apt-get "${opts[@]}" source lammps || ((DRY)) ||
    echo "bench_vs_lammps: apt-get source failed; unpacking the downloaded tarballs by hand" >&2
  local src
  src=$( ( ls -d "$PEER_DIR"/lammps-*/ 2>/dev/null || true ) | head -1)
  if [[ -z "$src" ]] && ! ((DRY)); then
    local orig deb
    orig=$( ( ls "$PEER_DIR"/lammps_*.orig.tar.* 2>/dev/null || true ) | head -1)
    deb=$( ( ls "$PEER_DIR"/lammps_*.debian.tar.* 2>/dev/null || true ) | head -1)
    [[ -n "$orig" ]] || { echo "bench_vs_lammps: apt-get source lammps downloaded no upstream tarball into $PEER_DIR" >&2; exit 1; }
    local ver
    ver=$(basename "$orig" | sed -E 's/^lammps_(.*)\.orig\.tar\..*$/\1/')
    src="$PEER_DIR/lammps-$ver/"
    run mkdir -p "$src"
    run tar -xf "$orig" -C "$src" --strip-components=1
    if [[ -n "$deb" ]]; then
      run tar -xf "$deb" -C "$src"
      local p
      while read -r p; do
        [[ -z "$p" || "$p" == \#* ]] && continue
        run patch -d "$src" -p1 -s -i "debian/patches/$p"
      done <"${src}debian/patches/series"
    fi
  fi
  ((DRY)) && src="$PEER_DIR/lammps-<version>/"
  [[ -n "$src" ]] || { echo "bench_vs_lammps: apt-get source lammps left no lammps-*/ in $PEER_DIR" >&2; exit 1; }
  case "$src" in *20250204*|*"<version>"*) ;; *) echo "bench_vs_lammps: warning: $src is not upstream 20250204, the version of the published comparisons" >&2 ;; esac
  run cmake -S "${src}cmake" -B "$PEER_DIR/build" -D CMAKE_BUILD_TYPE=Release -D BUILD_MPI=yes \
    -D BUILD_OMP=no -D PKG_SPH=yes -D PKG_GRANULAR=yes -D PKG_BPM=yes -D PKG_MOLECULE=yes
  run cmake --build "$PEER_DIR/build" -j2
}

if ! peer=$(find_peer); then
  if ((BUILD_PEER)); then
    build_peer
    peer="$PEER_DIR/build/lmp"
    ((DRY)) || has_sph "$peer" || { echo "bench_vs_lammps: the peer build gave no lmp with SPH at $peer" >&2; exit 1; }
  elif ((DRY)); then
    peer="lmp"
    echo "# no LAMMPS with the SPH package found (--lmp, \$LMP, lmp on PATH, $PEER_DIR/build/lmp);"
    echo "# a real run needs one: add --build-peer"
  else
    echo "bench_vs_lammps: no LAMMPS with the SPH package (tried --lmp, \$LMP, lmp on PATH," \
      "$PEER_DIR/build/lmp); add --build-peer to build it from Debian's source package" >&2
    exit 1
  fi
fi
if ! ((DRY)); then
  [[ -z "$SPH_CASES" || -x "$BENCH" ]] || { echo "bench_vs_lammps: no $BENCH (cmake --preset release && cmake --build build/release --target bench_sph)" >&2; exit 1; }
  [[ -z "$DEM_CASES" || -x "$BENCH_DEM" ]] || { echo "bench_vs_lammps: no $BENCH_DEM (cmake --preset release && cmake --build build/release --target bench_dem)" >&2; exit 1; }
  [[ -z "$DEM_CASES" ]] || "$peer" -h 2>/dev/null | grep -w BPM >/dev/null || { echo "bench_vs_lammps: $peer has no BPM package (needed by $DEM_CASES)" >&2; exit 1; }
  [[ -z "$PIN" ]] || command -v taskset >/dev/null || { echo "bench_vs_lammps: --pin needs taskset (Debian package util-linux)" >&2; exit 1; }
  command -v hyperfine >/dev/null || { echo "bench_vs_lammps: hyperfine is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
fi

sets=""
for s in "${DEFAULT_SETS[@]}" "${SETS[@]}"; do sets+=" --set $s"; done
mpi="mpirun --oversubscribe"
# Pinned: taskset's CPU list is inherited by mpirun and every rank.
[[ -n "$PIN" ]] && mpi="taskset -c $PIN $mpi"
[[ $(id -u) -eq 0 ]] && mpi+=" --allow-run-as-root"

run mkdir -p "$OUT"
for c in $SPH_CASES; do
  case "$c" in
    21k) nx=320; ny=60 ;;
    99k) nx=720; ny=132 ;;
  esac
  # Rounds outermost: the rank counts alternate too, so the speed-up from
  # one rank count to another compares runs of the same minutes.
  for k in $(seq "$ROUNDS"); do
    for r in $RANKS; do
      # The three commands of a round for N steps, named with SUFFIX.
      commands() {
        local n="$1" suffix="$2"
        local lmp_cmd="$mpi -n $r $peer -in $DECK -var nx $nx -var ny $ny -var nsteps $n -log none -screen none"
        printf '%s\0' -n "sphdem$suffix" "$mpi -n $r $BENCH --nx $nx --ny $ny --steps $n$sets" \
          -n "lammps_cont$suffix" "$lmp_cmd -var dens cont" -n "lammps_sum$suffix" "$lmp_cmd -var dens sum"
      }
      mapfile -d '' -t round < <(commands "$STEPS" "")
      ((STARTUP)) && mapfile -d '' -t -O "${#round[@]}" round < <(commands 0 _0)
      run hyperfine --runs 1 --style basic --export-json "$OUT/${c}_np${r}_round$k.json" "${round[@]}"
    done
  done
done
for c in $DEM_CASES; do
  case "$c" in
    bpm175) fibers=175; grid=(5 5 7) ;;
    bpm4800) fibers=4800; grid=(20 20 12) ;;
  esac
  for k in $(seq "$ROUNDS"); do
    for r in $RANKS; do
      ours="$mpi -n $r $BENCH_DEM --dim 3 --fibers $fibers --steps $DEM_STEPS --no-breakdown"
      lmp_cmd="cd $DEM_DECK_DIR && $mpi -n $r $peer -in in.bpm_fibers_3d -var nfx ${grid[0]} -var nfy ${grid[1]} -var nfz ${grid[2]} -var nsteps $DEM_STEPS -log none -screen none"
      run hyperfine --runs 1 --style basic --export-json "$OUT/${c}_np${r}_round$k.json" \
        -n sphdem "$ours" -n lammps_bpm "$lmp_cmd"
    done
  done
done
((DRY)) && exit 0

# Per round: sphdem / each peer mode and / the faster peer mode; median and range.
python3 - "$OUT" "$SPH_CASES" "$DEM_CASES" "$RANKS" "$ROUNDS" <<'EOF'
import json, statistics, sys
out, sph, dem, ranks, rounds = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4].split(), int(sys.argv[5])
cell = lambda v: f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})"
def times(c, r):  # one {command: wall time} per round
    return [{x["command"]: x["mean"] for x in json.load(open(f"{out}/{c}_np{r}_round{k}.json"))["results"]}
            for k in range(1, rounds + 1)]
if sph:
    print("| case | ranks | rounds | sphdem / LAMMPS continuity | sphdem / LAMMPS summation | sphdem / faster peer |")
    print("| --- | --- | --- | --- | --- | --- |")
    for c in sph:
        for r in ranks:
            t = times(c, r)
            cont = [x["sphdem"] / x["lammps_cont"] for x in t]
            summ = [x["sphdem"] / x["lammps_sum"] for x in t]
            best = [x["sphdem"] / min(x["lammps_cont"], x["lammps_sum"]) for x in t]
            print(f"| {c} | {r} | {rounds} | {cell(cont)} | {cell(summ)} | {cell(best)} |")
    # With --startup: the 0-step runs of the same rounds.
    if all("sphdem_0" in x for c in sph for r in ranks for x in times(c, r)):
        print("| case | ranks | 0 steps: sphdem [s] | 0 steps: faster peer mode [s] | steps alone: sphdem / faster peer |")
        print("| --- | --- | --- | --- | --- |")
        for c in sph:
            for r in ranks:
                t = times(c, r)
                fast = ["lammps_cont" if x["lammps_cont"] <= x["lammps_sum"] else "lammps_sum" for x in t]
                ours0 = [x["sphdem_0"] for x in t]
                peer0 = [x[f + "_0"] for x, f in zip(t, fast)]
                # (a round whose peer run was not longer than its 0-step run has none)
                alone = [(x["sphdem"] - x["sphdem_0"]) / (x[f] - x[f + "_0"])
                         for x, f in zip(t, fast) if x[f] > x[f + "_0"]]
                print(f"| {c} | {r} | {cell(ours0)} | {cell(peer0)} | {cell(alone) if alone else '-'} |")
if dem:
    print("| case | ranks | rounds | sphdem / LAMMPS BPM |")
    print("| --- | --- | --- | --- |")
    for c in dem:
        for r in ranks:
            print(f"| {c} | {r} | {rounds} | {cell([x['sphdem'] / x['lammps_bpm'] for x in times(c, r)])} |")
if len(ranks) > 1:
    print(f"| case | sphdem speed-up from {ranks[0]} rank(s), per rank count |")
    print("| --- | --- |")
    for c in sph + dem:
        base = times(c, ranks[0])
        ups = [f"{r}: {cell([b['sphdem'] / x['sphdem'] for b, x in zip(base, times(c, r))])}" for r in ranks[1:]]
        print(f"| {c} | {'; '.join(ups)} |")
EOF
