#!/usr/bin/env bash
# End-to-end test of scripts/slurm/perclod-array.sbatch on a one-node Slurm
# started on this machine (scripts/slurm/start-local-slurm.sh, needs root).
#
#   scripts/slurm/test-local-array.sh [--tasks N] [--quick]
#
# It writes a batch config listing the real models in ../shared/data (beside
# the repository; DATA=dir to use another: its OBJ and CityJSON files, such as
# a district split by scripts/split_cityjson.py), submits it as an N-task array
# (default 3) with `sbatch --wait`, and checks that
#   - every array task ended COMPLETED with exit code 0 (scontrol keeps
#     finished jobs for an hour in the local setup; no accounting needed),
#   - every model has exactly one complete output directory <out>/<model>/,
#     with a LOD per distance and a report, and no temporary directory is left,
#   - no model was processed by two tasks and none by no task (the shards
#     partition the list), judged from the models each task's log shows it
#     starting, and no shard's summary (out/batch_<i>_of_<n>.json) lists a failure,
#   - submitting the same array again processes nothing (finished models are
#     skipped without --force) and leaves the outputs untouched,
# and prints each task's wall time and the total. Exits non-zero on any failure.
#
# The run is kept small: distances 56 and 427 m, the four facade views, one
# sample per pixel, no Embree cross-check, no per-building labelling, no
# held-out judging. Measured on one core of a 2-core machine (shared with
# other builds), one model takes 10-30 s at these settings and
# ingolstadt_lod3_all53.obj (148k triangles) 40-80 s; the whole test with 3
# tasks takes about 1.5-2 minutes. --quick leaves the big models out (the
# block and the Delft tile, a CityJSON file of 432 buildings).
#
# Environment: PERCLOD (default build/perclod of this repository) is the binary
# the array runs; it must have `perclod run --shard`. Slurm daemons started by
# this script are stopped again at the end; ones already running are left so.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
tasks=3
quick=no
while [[ $# -gt 0 ]]; do
    case $1 in
        --tasks) tasks=$2; shift 2 ;;
        --quick) quick=yes; shift ;;
        *) echo "usage: $0 [--tasks N] [--quick]" >&2; exit 2 ;;
    esac
done
export PERCLOD=${PERCLOD:-$repo/build/perclod}
DATA=${DATA:-$repo/../shared/data}

failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
say() { echo "test-local-array: $*"; }

[[ -x $PERCLOD ]] || { echo "no perclod binary at $PERCLOD; set PERCLOD" >&2; exit 2; }
# The help read whole first: with pipefail, `grep -q` stopping at its match
# would fail the pipe by perclod's SIGPIPE once the help outgrew the pipe.
run_help=$("$PERCLOD" run --help 2>&1 || true)
if ! grep -q -- --shard <<<"$run_help"; then
    echo "$PERCLOD has no 'run --shard' (the batch feature); build a perclod that has it" >&2
    exit 2
fi
[[ -d $DATA ]] || { echo "no model directory $DATA; set DATA" >&2; exit 2; }

# --- Slurm -------------------------------------------------------------------
if scontrol ping >/dev/null 2>&1; then
    started_slurm=no
else
    started_slurm=yes
fi
if ! slurm_log=$("$here/start-local-slurm.sh" 2>&1); then
    echo "$slurm_log" >&2
    exit 1
fi
if [[ $started_slurm == yes ]]; then
    trap '"$here/start-local-slurm.sh" --stop >/dev/null 2>&1 || true' EXIT
fi

# --- The batch config --------------------------------------------------------
# Up axis per model: CityGML-derived data (Ingolstadt) is Z up, the rest Y up.
work=$(mktemp -d /tmp/perclod-slurm-test.XXXXXX)
config=$work/batch.yaml
models=()
{
    echo "# Written by scripts/slurm/test-local-array.sh"
    echo "display: $repo/configs/displays/paper-19in.yaml"
    echo "distances: [56, 427]"
    echo "views: facades"
    echo "samples: 1"
    echo "verify: false"
    echo "per_building: false"
    echo "judge_views: none"
    echo "out: $work/out"
    echo "models:"
    while IFS= read -r obj; do
        name=$(basename "$obj" .obj)
        name=${name%.city.json}
        if [[ ($name == ingolstadt_lod3_all53 || $name == 3dbag_5910_delft) && $quick == yes ]]; then continue; fi
        case $obj in */ingolstadt/*|*.city.json) up=z ;; *) up=y ;; esac
        echo "  - {model: $obj, up: $up}"
        models+=("$name")
    done < <(find "$(cd "$DATA" && pwd)" \( -name '*.obj' -o -name '*.city.json' \) | sort)
} >"$config"
say "$("$PERCLOD" --version 2>/dev/null || echo perclod) at $PERCLOD"
say "${#models[@]} models (${models[*]}), $tasks tasks; work dir $work"
cat "$config"

# --- Submit ------------------------------------------------------------------
# The job runs in $work; each task's log is $work/slurm-<job>_<task>.out.
submit() {
    sbatch --wait --parsable --array="0-$((tasks - 1))" --chdir="$work" \
        --output="$work/slurm-%A_%a.out" "$here/perclod-array.sbatch" "$config"
}
t0=$(date +%s)
rc=0
job=$(submit) || rc=$?
total=$(( $(date +%s) - t0 ))
job=${job%%;*}
say "array job $job finished in $total s (sbatch --wait exit $rc)"
[[ $rc == 0 ]] || fail "sbatch --wait exited $rc (the highest exit code of the tasks)"

# The models a task's log shows it working on: perclod's batch progress lines
# "[k/m NAME] start: ..." and the LOD files it names (NAME_lod_56m.obj).
task_models() {
    { grep -oE '^\[[0-9]+/[0-9]+ [^]]+\] start:' "$1" | sed -E 's/^\[[0-9]+\/[0-9]+ //; s/\] start:$//'
      grep -oE '[^/ ]+_lod_[0-9]+m\.(obj|glb)' "$1" | sed -E 's/_lod_[0-9]+m\..*//'
    } 2>/dev/null | sort -u || true
}

# --- Each task: state, exit code, wall time ----------------------------------
# scontrol prints one line per array task (in no particular order); their
# StartTime/EndTime give the wall time, to the second.
declare -A task_log
lines=$(scontrol -o show job "$job" \
    | awk '{ for (i = 1; i <= NF; i++) if ($i ~ /^ArrayTaskId=/) { split($i, a, "="); print a[2] "\t" $0 } }' \
    | sort -n | cut -f2-)
seen=0
while IFS= read -r line; do
    field() { grep -oE "(^| )$1=[^ ]*" <<<"$line" | head -1 | cut -d= -f2-; }
    id=$(field ArrayTaskId) state=$(field JobState) code=$(field ExitCode)
    wall=$(( $(date -d "$(field EndTime)" +%s) - $(date -d "$(field StartTime)" +%s) ))
    log=$work/slurm-${job}_$id.out
    task_log[$id]=$log
    mine=$(task_models "$log" | tr '\n' ' ')
    printf '  task %s: %s, exit %s, wall %s s, models: %s\n' "$id" "$state" "$code" "$wall" "${mine:-none}"
    [[ $state == COMPLETED && $code == 0:0 ]] || fail "task $id: $state, exit code $code (log $log)"
    seen=$((seen + 1))
done <<<"$lines"
[[ $seen == "$tasks" ]] || fail "scontrol shows $seen tasks of job $job, expected $tasks"

# --- Outputs: one complete directory per model, nothing else -----------------
for name in "${models[@]}"; do
    dir=$work/out/$name
    if [[ ! -d $dir ]]; then fail "$name: no output directory $dir"; continue; fi
    for d in 56 427; do
        compgen -G "$dir/${name}_lod_${d}m.*" >/dev/null || fail "$name: no LOD for $d m in $dir"
    done
    compgen -G "$dir/*report.json" >/dev/null || fail "$name: no report in $dir"
done
# Besides the models' folders out/ may hold each shard's summary
# (batch_<i>_of_<n>.json), the batch's tileset.json and index.html, the
# lock the shards take turns on (.batch.lock), the folder's lock they share
# (.perclod.lock) and each shard's own (.perclod-shard-<i>-of-<n>.lock). Anything else (a
# .NAME.partial-HOST-PID folder left behind, a second copy of a model under another
# name, a loose file) is a failure.
while IFS= read -r entry; do
    e=$(basename "$entry")
    case $e in .perclod.lock|.perclod-shard-*-of-*.lock|.batch.lock|tileset.json|index.html|batch_*_of_*.json) continue ;; esac
    printf '%s\n' "${models[@]}" | grep -qxF "$e" || fail "unexpected entry in out/: $e"
done < <(find "$work/out" -mindepth 1 -maxdepth 1)
# Each shard's summary must list no failed model.
for id in "${!task_log[@]}"; do
    summary=$work/out/batch_${id}_of_${tasks}.json
    if [[ ! -f $summary ]]; then fail "task $id wrote no summary $summary"; continue; fi
    python3 - "$summary" <<'PY' || fail "task $id: its summary lists failed models ($summary)"
import json, sys
s = json.load(open(sys.argv[1]))
bad = [m["name"] for m in s.get("models", []) if m.get("status") not in ("done", "skipped")]
sys.exit(1 if bad or s.get("failed", 0) else 0)
PY
done
# The batch tileset, written by every shard as it ends, must still name every
# model that has a tileset of its own (the last shard to end sees them all).
if [[ -f $work/out/tileset.json ]]; then
    for ts in "$work"/out/*/*_tileset.json; do
        [[ -e $ts ]] || continue
        grep -qF "$(basename "$ts")" "$work/out/tileset.json" \
            || fail "out/tileset.json does not reference $(basename "$(dirname "$ts")")"
    done
fi

# --- Shards partition the models ---------------------------------------------
# Each model must show up in exactly one task's log.
for name in "${models[@]}"; do
    owners=()
    for id in $(printf '%s\n' "${!task_log[@]}" | sort -n); do
        task_models "${task_log[$id]}" | grep -qxF "$name" && owners+=("$id")
    done
    case ${#owners[@]} in
        1) ;;
        0) fail "$name: processed by no task" ;;
        *) fail "$name: processed by tasks ${owners[*]}" ;;
    esac
done

# --- A second submission skips finished models -------------------------------
stamp=$work/before-rerun
touch "$stamp"
sleep 1
t0=$(date +%s)
rc=0
job2=$(submit) || rc=$?
job2=${job2%%;*}
say "re-run: array job $job2 finished in $(( $(date +%s) - t0 )) s (exit $rc)"
[[ $rc == 0 ]] || fail "re-run: sbatch --wait exited $rc"
# Only the models' folders count: each shard rewrites its summary and the
# batch tileset every time.
changed=$(find "$work/out" -mindepth 2 -type f -newer "$stamp" ! -name .perclod.lock | head -5)
[[ -z $changed ]] || fail "re-run rewrote finished outputs without --force, e.g.: $(tr '\n' ' ' <<<"$changed")"

say "total wall time of the first array: $total s; logs and outputs in $work"
if (( failures > 0 )); then
    say "$failures check(s) failed"
    exit 1
fi
say "all checks passed"
