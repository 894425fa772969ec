#!/usr/bin/env bash
# Long fuzzing campaigns of every file loader (tests/fuzz, docs/reliability.md)
# in the sanitizer build (build-asan/, clang, ASan + UBSan + libFuzzer).
#
#   scripts/fuzz.sh                    every target, 1,000,000 executions each
#   scripts/fuzz.sh -n 200000 obj bvh  these targets, this many executions
#   scripts/fuzz.sh --no-leak-check fbx  LeakSanitizer off (ASan and UBSan stay on)
#
# --no-leak-check is for the fbx target: assimp leaks on most damaged FBX
# files (suppressed, tests/fuzz/lsan.supp), and each such input costs a full
# leak check, 90 inputs/s instead of 1,700 (docs/reliability.md).
#
# Each target starts from its seeds (tests/fuzz/seeds/<target>) and the corpus
# earlier runs grew (build-asan/tests/fuzz/corpus/<target>). A finding stops
# the target and is kept as build-asan/tests/fuzz/findings/<target>-crash-*;
# fix it, then copy the input into the seeds as a regression case. One line
# per target goes to build-asan/fuzz-report.tsv.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
runs=1000000
leaks=1
while [ $# -gt 0 ]; do
  case "$1" in
    -n) runs="$2"; shift 2 ;;
    --no-leak-check) leaks=0; shift ;;
    *) break ;;
  esac
done
"$root/scripts/sanitize.sh" --build-only fuzz_targets
fuzz="$root/build-asan/tests/fuzz"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=($(cd "$fuzz" && ls fuzz_* | sed 's/^fuzz_//'))
fi
report="$root/build-asan/fuzz-report.tsv"
export ASAN_OPTIONS=detect_leaks=$leaks:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0"
[ -f "$report" ] || printf 'date\ttarget\texecutions\tseconds\tcorpus\tresult\n' >"$report"
status=0
for t in "${targets[@]}"; do
  mkdir -p "$fuzz/corpus/$t" "$fuzz/findings"
  log="$fuzz/$t.log"
  start=$(date +%s)
  echo "fuzz_$t: $runs executions (log: $log)"
  if "$fuzz/fuzz_$t" -runs="$runs" -detect_leaks="$leaks" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$fuzz/findings/$t-" "$fuzz/corpus/$t" "$root/tests/fuzz/seeds/$t" >"$log" 2>&1; then
    result=clean
  else
    result="FINDING (see $log)"
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(ls "$fuzz/corpus/$t" | wc -l)
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%F)" "$t" "${execs:-?}" "$(($(date +%s) - start))" "$corpus" \
    "$result$([ $leaks = 1 ] || echo ' (no leak check)')" | tee -a "$report"
done
exit $status
