#!/bin/bash
# The paper comparison with several fiber placements (docs/paper-comparison.md,
# "Seeds: torque and glass"): the 3.8 % plate with E = 1e8 fibers and with glass
# fibers, and the breakage case, each for several values of fibers.seed, one run
# at a time, every run timed with /usr/bin/time -v. Then tools/paper_seeds.py
# tabulates orientation, bond stress, breakage and cost with the spread between
# seeds and draws the figures.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: tools/paper_seeds.sh [options]

Runs, for each seed, the E = 1e8 plate (inputs/plate_fibers_3.8.yaml), then
the glass plate (inputs/plate_fibers_glass.yaml), alternated so that their
user-CPU ratio holds on a loaded machine, then the breakage case
(inputs/plate_breakage.yaml); each as
  nice -n NICE [timeout S] /usr/bin/time -v -o OUT/NAME.time \
      mpirun -n RANKS SPHDEM run CASE -o OUT/NAME --set fibers.seed=SEED \
      --set numerics.end_time=T --set output.every_time=DT --overwrite
with NAME = e1e8_sSEED, glass_sSEED or breakage_sSEED and the log in
OUT/NAME.log. Then tools/paper_seeds.py OUT (unless --no-analysis).
The defaults are the full runs (the cases' own end times); docs/paper-comparison.md
says which shorter ones were made and why.

options:
  --out DIR             output directory (default out/paper_seeds)
  --sphdem PATH         the binary (default build/release/sphdem, else build/test/sphdem)
  --ranks N             MPI ranks per run (default 2)
  --seeds "S1 S2 ..."   fiber placement seeds (default "1 2 3")
  --cases "C1 C2 ..."   any of e1e8 glass breakage (default all three)
  --plate-end T         end time of both plates [s] (default 0.12, the cases')
  --plate-every DT      their snapshot interval [s] (default 2e-3, the cases')
  --breakage-end T      end time of the breakage case [s] (default 0.012)
  --breakage-every DT   its snapshot interval [s] (default 1e-3)
  --timeout S           wall-clock budget per run [s] (default none); a run
                        that exceeds it is stopped and the script goes on
  --nice N              niceness (default 10)
  --skip-existing       skip a run that finished (OUT/NAME.log has sphdem's
                        "done:" line); an interrupted run is run again
  --no-analysis         only the runs
  --dry-run             print the commands, run nothing
  -h, --help            this text

examples (the short runs of docs/paper-comparison.md section 13, on a loaded machine):
  tools/paper_seeds.sh --ranks 1 --plate-end 0.01 --plate-every 1e-3 \
      --breakage-end 3e-4 --breakage-every 5e-5 --timeout 900
  tools/paper_seeds.sh --ranks 1 --cases breakage --out out/paper_seeds_breakage \
      --breakage-end 2e-3 --breakage-every 2e-4 --timeout 240
EOF
}

out=out/paper_seeds
sphdem=""
ranks=2
seeds="1 2 3"
cases="e1e8 glass breakage"
plate_end=0.12
plate_every=2e-3
breakage_end=0.012
breakage_every=1e-3
timeout_s=""
niceness=10
skip=0
analysis=1
dry=0

need() { [[ $# -ge 2 && -n "$2" ]] || { echo "paper_seeds.sh: error: $1 needs a value" >&2; exit 2; }; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --out) need "$@"; out=$2; shift 2 ;;
    --sphdem) need "$@"; sphdem=$2; shift 2 ;;
    --ranks) need "$@"; ranks=$2; shift 2 ;;
    --seeds) need "$@"; seeds=$2; shift 2 ;;
    --cases) need "$@"; cases=$2; shift 2 ;;
    --plate-end) need "$@"; plate_end=$2; shift 2 ;;
    --plate-every) need "$@"; plate_every=$2; shift 2 ;;
    --breakage-end) need "$@"; breakage_end=$2; shift 2 ;;
    --breakage-every) need "$@"; breakage_every=$2; shift 2 ;;
    --timeout) need "$@"; timeout_s=$2; shift 2 ;;
    --nice) need "$@"; niceness=$2; shift 2 ;;
    --skip-existing) skip=1; shift ;;
    --no-analysis) analysis=0; shift ;;
    --dry-run) dry=1; shift ;;
    *) echo "paper_seeds.sh: error: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done

for c in $cases; do
  case "$c" in e1e8|glass|breakage) ;; *)
    echo "paper_seeds.sh: error: unknown case '$c' in --cases (e1e8, glass, breakage)" >&2; exit 2 ;;
  esac
done
if [[ -z "$sphdem" ]]; then
  if [[ -x build/release/sphdem ]]; then sphdem=build/release/sphdem; else sphdem=build/test/sphdem; fi
fi
if [[ $dry -eq 0 && ! -x "$sphdem" ]]; then
  echo "paper_seeds.sh: error: no sphdem binary at '$sphdem' (build it or pass --sphdem)" >&2; exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)

one_run() {  # NAME CASE_FILE SEED END EVERY
  local name=$1 file=$2 seed=$3 end=$4 every=$5
  # /usr/bin/time writes OUT/NAME.time when a run starts, so only the log's
  # "done:" line says that the run finished.
  if [[ $skip -eq 1 ]] && grep -q '^done:' "$out/$name.log" 2>/dev/null; then
    echo "skip $name ($out/$name.log says done)"; return 0
  fi
  local cmd=(nice -n "$niceness")
  [[ -n "$timeout_s" ]] && cmd+=(timeout "$timeout_s")
  cmd+=(/usr/bin/time -v -o "$out/$name.time" mpirun -n "$ranks" "$sphdem" run "$file" -o "$out/$name"
        --set "fibers.seed=$seed" --set "numerics.end_time=$end" --set "output.every_time=$every"
        --overwrite)
  echo "$(date -u +%H:%M:%S) $name: ${cmd[*]}"
  [[ $dry -eq 1 ]] && return 0
  local rc=0
  "${cmd[@]}" >"$out/$name.log" 2>&1 || rc=$?
  echo "$(date -u +%H:%M:%S) $name: exit $rc, $(grep -h '^done:' "$out/$name.log" || echo 'no done line')"
  [[ $rc -eq 124 ]] && echo "timed out after $timeout_s s" >>"$out/$name.log"
  return 0
}

[[ $dry -eq 1 ]] || mkdir -p "$out"
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
for s in $seeds; do
  for c in $cases; do
    case "$c" in
      e1e8) one_run "e1e8_s$s" inputs/plate_fibers_3.8.yaml "$s" "$plate_end" "$plate_every" ;;
      glass) one_run "glass_s$s" inputs/plate_fibers_glass.yaml "$s" "$plate_end" "$plate_every" ;;
      breakage) one_run "breakage_s$s" inputs/plate_breakage.yaml "$s" "$breakage_end" "$breakage_every" ;;
    esac
    echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
  done
done
if [[ $analysis -eq 1 && $dry -eq 0 ]]; then
  /usr/bin/python3 "$here/paper_seeds.py" "$out"
fi
