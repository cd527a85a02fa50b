#!/usr/bin/env bash
# Fuzz perclod's file readers with libFuzzer (targets in tests/fuzz/: OBJ,
# labels, YAML, the assimp formats and CityJSON; built with ASan + UBSan in
# build-asan/ by scripts/build-asan.sh).
#
#   scripts/fuzz.sh                     # every target, 10 minutes each
#   scripts/fuzz.sh --seconds 60 fuzz_obj fuzz_labels
#   nice -n 10 scripts/fuzz.sh --seconds 3600 fuzz_cityjson   # the hour of docs/ci.md
#   FUZZ_SECONDS=3600 scripts/fuzz.sh   # same as --seconds
#   scripts/fuzz.sh --keep-going        # -fork=1: go on after a finding, collect them all
#   scripts/fuzz.sh --no-build          # use the targets already in build-asan/
#   scripts/fuzz.sh --seed 1            # libFuzzer -seed: the same mutations every run (CI)
#   scripts/fuzz.sh --parallel 2        # targets at once (default 1); each is one process
#
# Each target starts from its committed seeds (tests/fuzz/corpus/<target>/)
# plus whatever earlier runs added to build-asan/fuzz/<target>/corpus/, and
# writes reproducers to build-asan/fuzz/<target>/findings/. A finding is a
# crash, a sanitizer report, an input that runs over 10 s (-timeout) or over
# 2 GB (-rss_limit_mb, also the single-malloc limit), or a leak; a
# std::exception is not one. Prints one line per target (executions, time,
# coverage, findings) and a last line `N passed, N failed`; exits non-zero
# when any target found something.
# Reproduce a finding: build-asan/tests/fuzz/<target> <file>
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${FUZZ_SECONDS:-600}
fork=()
seed=()
build=1
parallel=1
targets=()
while (($#)); do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --keep-going) fork=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1); shift ;;
    --no-build) build=0; shift ;;
    --seed) seed=(-seed="$2"); shift 2 ;;
    --parallel) parallel=$2; shift 2 ;;
    -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
    *) targets+=("$1"); shift ;;
  esac
done
if ((${#targets[@]} == 0)); then
  for d in tests/fuzz/corpus/*/; do targets+=("$(basename "$d")"); done
fi

((build)) && scripts/build-asan.sh "${targets[@]}" >/dev/null

# Leaks inside Debian's assimp are not perclod's (tests/lsan.supp says which).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp}

# One target; its summary line goes to $work/summary, its status (0: no
# finding) to $work/status.
fuzz_target() {
  local t=$1 work=build-asan/fuzz/$1
  mkdir -p "$work/corpus" "$work/findings"
  local log=$work/log.txt
  echo "fuzz: $t for ${seconds}s (log: $log)"
  local rc=0 start
  start=$(date +%s)
  build-asan/tests/fuzz/"$t" "$work/corpus" "tests/fuzz/corpus/$t" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/findings/" "${seed[@]}" "${fork[@]}" >"$log" 2>&1 || rc=$?
  local elapsed=$(($(date +%s) - start))
  # Executions: the final stats, else (fork mode) the last status line "#N ...".
  local execs cov corpus findings
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  [[ -n "$execs" ]] || execs=$({ grep -oE '^#[0-9]+' "$log" || true; } | tail -1 | tr -d '#')
  cov=$({ grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" || true; } | tail -1)
  corpus=$(find "$work/corpus" -type f | wc -l)
  findings=$({ grep -oE 'Test unit written to [^ ]+' "$log" || true; } | sed 's/Test unit written to //' | sort -u | tr '\n' ' ')
  local line="$t: ${execs:-0} executions in ${elapsed}s, ${cov:-cov: ?}, corpus $corpus"
  if ((rc == 0)) && [[ -z "$findings" ]]; then
    echo "$line: no finding" >"$work/summary"
    echo 0 >"$work/status"
  else
    local what
    what=$(grep -m1 -E '^SUMMARY:|ERROR: libFuzzer:|==ERROR:' "$log" || true)
    echo "$line: FINDING (exit $rc) ${what} ${findings:+-> $findings}" >"$work/summary"
    echo 1 >"$work/status"
  fi
}

for t in "${targets[@]}"; do
  rm -f "build-asan/fuzz/$t/summary" "build-asan/fuzz/$t/status"
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  fuzz_target "$t" &
done
wait

passed=0
failed=0
for t in "${targets[@]}"; do
  work=build-asan/fuzz/$t
  if [[ "$(cat "$work/status" 2>/dev/null)" == 0 ]]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
  fi
  cat "$work/summary" 2>/dev/null || echo "$t: no result (the fuzzing script failed)"
done
echo "$passed passed, $failed failed"
((failed == 0))
