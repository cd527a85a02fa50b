#!/usr/bin/env bash
# Whole-run cost beside bare rendering (issue "Speed"): a generated facade of
# about N triangles, the default views (facades,ring8el30,ring8el60,top) at
# 56, 132 and 427 m, 4 samples per pixel, fidelity mode. Each row is one process timed
# by /usr/bin/time (wall, CPU share of the 2 cores, peak resident memory);
# ratios are to the bare renders of the same run of this script.
#
#   tests/bench/bench_run.sh [--triangles N] [--views SET] [--build DIR] [--work DIR] [--runs K]
#
# --views labels (and renders) another view set than the default, e.g. the
# previous default facades,ring8el30,top, to compare view sets in one session.
#
# Rows (medians of K runs):
#   render: labelling views   perclod render of the labelling views (and tiles)
#   render: + held-out views  the same plus the nine held-out views a run judges from
#   run                       perclod run, every debug image on, verify off
#   run, no debug images      debug_images: false
#   run, no held-out views    judge_views: none, debug_images: false
#   run, verify               verify: true (Embree beside the octree on every view)
#   render: + LODs, every view  every render a run makes: row 2, then each LOD
#                             of a run from the labelling and held-out views
#                             at its distance (the judging renders)
set -euo pipefail

triangles=1000000
views="facades,ring8el30,ring8el60,top"  # kDefaultViews (perclod/views.h)
build="$(cd "$(dirname "$0")/../.." && pwd)/build"
work="${TMPDIR:-/tmp}/perclod-bench-run"
runs=1
while [ $# -gt 0 ]; do
  case "$1" in
    --triangles) triangles="$2"; shift 2 ;;
    --views) views="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) echo "bench_run.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
perclod="$build/perclod"
[ -x "$perclod" ] || { echo "bench_run.sh: $perclod not found: build first (scripts/setup.sh)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench_run.sh: /usr/bin/time is missing (apt-get install time)" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
model="$work/facade.obj"
"$perclod" generate facade --triangles "$triangles" "$model" >/dev/null 2>&1
config() {  # name, extra YAML lines
  printf 'model: %s\nup: z\ndistances: [56, 132, 427]\nviews: %s\nsamples: 4\nout: %s\n%s' \
    "$model" "$views" "$work/out-$1" "$2" >"$work/$1.yaml"
}
config run ""
config nodebug "debug_images: false"$'\n'
config noheld "debug_images: false"$'\n'"judge_views: none"$'\n'
config verify "verify: true"$'\n'

# time_it NAME COMMAND...: K runs; prints "NAME wall cpu% peak_MiB" (medians).
time_it() {
  local name="$1"; shift
  local walls=() cpus=() mems=()
  for _ in $(seq "$runs"); do
    rm -rf "$work"/out-*
    /usr/bin/time -f "%e %P %M" -o "$work/time.txt" "$@" >/dev/null 2>"$work/stderr.txt" ||
      { echo "bench_run.sh: $name failed:" >&2; tail -5 "$work/stderr.txt" >&2; exit 1; }
    read -r wall cpu mem <"$work/time.txt"
    walls+=("$wall"); cpus+=("${cpu%\%}"); mems+=("$mem")
  done
  median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
  echo "$name|$(median "${walls[@]}")|$(median "${cpus[@]}")|$(median "${mems[@]}")"
}

results="$work/results.txt"
: >"$results"
echo "bench_run: facade of $("$perclod" info "$model" --json | sed -n 's/.*"triangles": *\([0-9]*\).*/\1/p' | head -1) triangles, $runs run(s) per row, $(nproc) cores, views $views" >&2
time_it "render: labelling views" "$perclod" render "$model" --up z -d 56,132,427 --views "$views" -o "$work/out-render" >>"$results"
time_it "render: + held-out views" "$perclod" render "$model" --up z -d 56,132,427 --views "$views,held_out" -o "$work/out-render" >>"$results"
time_it "run" "$perclod" run "$work/run.yaml" >>"$results"
time_it "run, no debug images" "$perclod" run "$work/nodebug.yaml" >>"$results"
time_it "run, no held-out views" "$perclod" run "$work/noheld.yaml" >>"$results"
time_it "run, verify" "$perclod" run "$work/verify.yaml" >>"$results"
# Every render a run makes: the original from the labelling and held-out
# views (row 2) and each LOD of the run from the same views at its distance
# (the judging renders). The LODs are the verify row's last run's (verify
# traces Embree beside the octree; the labels and LODs are the run's).
rm -rf "$work/lods"
mkdir -p "$work/lods"
cp "$work"/out-verify/facade_lod_*m.obj "$work/lods/"
cat >"$work/render_all.sh" <<EOF
set -e
"$perclod" render "$model" --up z -d 56,132,427 --views "$views,held_out" -o "$work/out-render"
for d in 56 132 427; do
  "$perclod" render "$work/lods/facade_lod_\${d}m.obj" --up z -d "\$d" --views "$views,held_out" -o "$work/out-render"
done
EOF
time_it "render: + LODs, every view" bash "$work/render_all.sh" >>"$results"

awk -F'|' '
  NR == 1 { r1 = $2 } NR == 2 { r2 = $2 } NR == 3 { run = $2 } NR == 7 { every = $2 }
  { rows[NR] = $0; wall[NR] = $2 }
  END {
    printf "| %-26s | %8s | %5s | %9s | %14s | %14s | %14s | %8s |\n", "row", "wall s", "CPU", "peak MiB", "/ render label", "/ render all", "/ every render", "/ run"
    for (i = 1; i <= NR; ++i) {
      split(rows[i], f, "|")
      printf "| %-26s | %8.1f | %4d%% | %9.0f | %14.2f | %14.2f | %14.2f | %8.2f |\n", f[1], f[2], f[3], f[4] / 1024, f[2] / r1, f[2] / r2, f[2] / every, f[2] / run
    }
  }' "$results"
