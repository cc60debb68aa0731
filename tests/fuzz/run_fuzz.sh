#!/usr/bin/env bash
# One bounded libFuzzer run as a ctest (label fuzz): a fresh seed corpus,
# SECONDS of fuzzing, non-zero exit (and the crashing input kept under
# WORK/artifacts/) on any finding: a crash, ASan/UBSan report, leak, timeout,
# out-of-memory or a harness check.
#   run_fuzz.sh FUZZER SEEDER KIND WORK SECONDS [libFuzzer options...]
set -euo pipefail
fuzzer=$1 seeder=$2 kind=$3 work=$4 seconds=$5
shift 5
rm -rf "$work/corpus" "$work/seeds"
mkdir -p "$work/corpus" "$work/seeds" "$work/artifacts"
"$seeder" "$work/seeds" "$kind"
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=0:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
echo "fuzz $kind: $(ls "$work/seeds" | wc -l) seeds, ${seconds}s"
rc=0
"$fuzzer" -max_total_time="$seconds" -timeout=30 -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
  "$@" "$work/corpus" "$work/seeds" >"$work/fuzz.log" 2>&1 || rc=$?
# The libFuzzer summary (runs, coverage, corpus) and, on a finding, the report.
if [ "$rc" -ne 0 ]; then
  tail -n 80 "$work/fuzz.log"
  echo "fuzz $kind: FINDING (exit $rc); input in $work/artifacts/, log in $work/fuzz.log"
else
  grep -E '^#[0-9]+[[:space:]]+DONE|^Done [0-9]+ runs|stat::' "$work/fuzz.log" || tail -n 5 "$work/fuzz.log"
fi
exit "$rc"
