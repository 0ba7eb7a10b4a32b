#!/usr/bin/env bash
# Runs the libFuzzer harnesses (README "Fuzzing and sanitizers"):
#   tests/fuzz/run.sh BUILD_DIR --seconds S [--jobs J] [harness...]   each harness for S seconds (make fuzz)
#   tests/fuzz/run.sh BUILD_DIR --runs N [--out FILE] [harness...]    each until N executions (make fuzz-long)
# Both --runs and --seconds: whichever limit comes first.
# BUILD_DIR is a build configured with clang and -DTRAILSCOPE_FUZZ=ON whose `fuzzers` target is built.
# Each harness starts from BUILD_DIR/fuzz-corpus/<harness> (seeds.sh; new inputs are added there) plus the
# committed seeds and crash reproducers (tests/fuzz/seeds/<harness>, tests/fuzz/regressions/<harness>).
# A crash, a sanitizer report, a leak, a timeout (10 s for one input) or an RSS above 2 GiB is a failure:
# libFuzzer writes the input to BUILD_DIR/fuzz-artifacts/<harness>/ and the script exits non-zero after
# all harnesses ran. One JSON line per harness (executions, exec/s, coverage cov/ft, corpus size, wall
# time, outcome) goes to --out (default BUILD_DIR/fuzz-results.jsonl).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?usage: run.sh BUILD_DIR (--seconds S | --runs N) [--jobs J] [--out FILE] [harness...]}
shift
seconds="" runs="" jobs=1 out="$build/fuzz-results.jsonl" harnesses=()
while [ $# -gt 0 ]; do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
[ -n "$seconds$runs" ] || { echo "run.sh: give --seconds or --runs" >&2; exit 2; }
if [ ${#harnesses[@]} -eq 0 ]; then
  for f in "$here"/*_fuzz.cpp; do n=$(basename "$f" .cpp); harnesses+=("${n%_fuzz}"); done
fi
for h in "${harnesses[@]}"; do
  [ -x "$build/tests/fuzz/${h}_fuzz" ] || { echo "run.sh: $build/tests/fuzz/${h}_fuzz not built (make fuzz builds it)" >&2; exit 2; }
done
logs=$build/fuzz-logs
mkdir -p "$logs"
: > "$out"

# UBSan aborts on the first report (the code is built with -fno-sanitize-recover too); LSan reports leaks.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}

one() {
  local h=$1 bin="$build/tests/fuzz/${1}_fuzz" log="$logs/$1.log"
  local corpus="$build/fuzz-corpus/$h" art="$build/fuzz-artifacts/$h/"
  mkdir -p "$corpus" "$art"
  local dirs=("$corpus")
  for d in "$here/seeds/$h" "$here/regressions/$h"; do [ -d "$d" ] && dirs+=("$d"); done
  local limit=()
  [ -n "$seconds" ] && limit+=(-max_total_time="$seconds")
  [ -n "$runs" ] && limit+=(-runs="$runs")
  local t0=$SECONDS rc
  "$bin" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$art" "${dirs[@]}" > "$log" 2>&1
  rc=$?
  local wall=$((SECONDS - t0))
  # libFuzzer's final statistics and its last status line ("#N DONE cov: C ft: F corp: K/S ...").
  local execs rate cov ft corp
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -oE ' cov: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  ft=$(grep -oE ' ft: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  corp=$(grep -oE ' corp: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  local outcome=ok
  [ $rc -ne 0 ] && outcome="failed (exit $rc; see $log and $art)"
  printf '{"bench":"fuzz","harness":"%s","mode":"%s","executions":%s,"exec_per_s":%s,"cov":%s,"ft":%s,"corpus":%s,"wall_s":%s,"exit":%s,"outcome":"%s"}\n' \
    "$h" "${runs:+runs=$runs }${seconds:+seconds=$seconds}" "${execs:-0}" "${rate:-0}" "${cov:-0}" "${ft:-0}" \
    "${corp:-0}" "$wall" "$rc" "$outcome" >> "$out"
  printf '%-22s %10s execs %7s/s cov %5s ft %6s  %s\n' "$h" "${execs:-0}" "${rate:-0}" "${cov:-0}" "${ft:-0}" "$outcome"
  return $rc
}

failed=0
if [ "$jobs" -le 1 ]; then
  for h in "${harnesses[@]}"; do one "$h" || failed=1; done
else
  export -f one
  export build here seconds runs out logs
  printf '%s\n' "${harnesses[@]}" | xargs -P "$jobs" -I{} bash -c 'one {}' || failed=1
fi
[ $failed -eq 0 ] || { echo "run.sh: a harness failed; the inputs are under $build/fuzz-artifacts/" >&2; exit 1; }
