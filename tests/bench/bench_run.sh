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
# Rows (medians over K rounds, every row once per round):
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

# The rows are run in rounds (every row once per round, K rounds), so a slow
# spell of a shared machine falls on every row alike; each ratio is taken
# within a round, and the table gives medians over the rounds.
names=("render: labelling views" "render: + held-out views" "run" "run, no debug images"
       "run, no held-out views" "run, verify" "render: + LODs, every view")
# Every render a run makes: the original from the labelling and held-out
# views (row 2) and each LOD of a run from the same views at its distance
# (the judging renders). The LODs are this round's verify run's (verify
# traces Embree beside the octree; the labels and LODs are the run's).
run_row() {  # row index: runs that row's command
  case "$1" in
    0) "$perclod" render "$model" --up z -d 56,132,427 --views "$views" -o "$work/out-render" ;;
    1) "$perclod" render "$model" --up z -d 56,132,427 --views "$views,held_out" -o "$work/out-render" ;;
    2) "$perclod" run "$work/run.yaml" ;;
    3) "$perclod" run "$work/nodebug.yaml" ;;
    4) "$perclod" run "$work/noheld.yaml" ;;
    5) "$perclod" run "$work/verify.yaml" ;;
    6) run_row 1 &&
       for d in 56 132 427; do
         "$perclod" render "$work/lods/facade_lod_${d}m.obj" --up z -d "$d" --views "$views,held_out" -o "$work/out-render" || exit
       done ;;
  esac
}
export -f run_row
export perclod model views work

times="$work/times.txt"  # round row wall cpu% peak_KiB
: >"$times"
echo "bench_run: facade of $("$perclod" info "$model" --json | sed -n 's/.*"triangles": *\([0-9]*\).*/\1/p' | head -1) triangles, $runs round(s) of every row, $(nproc) cores, views $views" >&2
for round in $(seq "$runs"); do
  for i in "${!names[@]}"; do
    rm -rf "$work"/out-*
    /usr/bin/time -f "%e %P %M" -o "$work/time.txt" bash -c "run_row $i" >/dev/null 2>"$work/stderr.txt" ||
      { echo "bench_run.sh: ${names[$i]} failed:" >&2; tail -5 "$work/stderr.txt" >&2; exit 1; }
    read -r wall cpu mem <"$work/time.txt"
    echo "$round $i $wall ${cpu%\%} $mem" >>"$times"
    if [ "$i" = 5 ]; then
      rm -rf "$work/lods" && mkdir -p "$work/lods"
      cp "$work"/out-verify/facade_lod_*m.obj "$work/lods/"
    fi
  done
done

printf '%s\n' "${names[@]}" >"$work/names.txt"
awk '
  function median(list,   n, a, i, j, t) {
    n = split(list, a, " ")
    for (i = 2; i <= n; ++i)
      for (j = i; j > 1 && a[j - 1] + 0 > a[j] + 0; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
  }
  FNR == NR { name[FNR - 1] = $0; rows = FNR; next }
  { wall[$1, $2] = $3; cpu[$1, $2] = $4; mem[$1, $2] = $5; if ($1 > rounds) rounds = $1 }
  END {
    printf "| %-26s | %8s | %5s | %9s | %14s | %14s | %14s | %8s |\n", "row", "wall s", "CPU", "peak MiB",
           "/ render label", "/ render all", "/ every render", "/ run"
    for (i = 0; i < rows; ++i) {
      w = c = m = r0 = r1 = r6 = r2 = ""
      for (k = 1; k <= rounds; ++k) {
        w = w " " wall[k, i]; c = c " " cpu[k, i]; m = m " " mem[k, i] / 1024
        r0 = r0 " " wall[k, i] / wall[k, 0]; r1 = r1 " " wall[k, i] / wall[k, 1]
        r6 = r6 " " wall[k, i] / wall[k, 6]; r2 = r2 " " wall[k, i] / wall[k, 2]
      }
      printf "| %-26s | %8.1f | %4d%% | %9.0f | %14.2f | %14.2f | %14.2f | %8.2f |\n", name[i], median(w),
             median(c), median(m), median(r0), median(r1), median(r6), median(r2)
    }
    printf "(medians over %d round(s); each ratio is taken within a round)\n", rounds
  }' "$work/names.txt" "$times"
