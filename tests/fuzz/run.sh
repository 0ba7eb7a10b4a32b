#!/usr/bin/env bash
# Runs the libFuzzer harnesses (README "Fuzzing and sanitizers"). Two modes:
#
#   tests/fuzz/run.sh BUILD_DIR --seconds S [--jobs J] [--out FILE] [harness...]
#     each harness for S seconds (make fuzz, CI), from BUILD_DIR/fuzz-corpus/<harness> (seeds.sh; new
#     inputs are added there). One JSON line per harness goes to --out (default BUILD_DIR/fuzz-results.jsonl,
#     rewritten).
#
#   tests/fuzz/run.sh BUILD_DIR --long [--goal N] [--max-seconds S] [--timeout T] [--out FILE] [harness...]
#     one segment of the long run (make fuzz-long): each harness that has not yet reached N executions
#     (default 10,000,000) in the segments recorded in --out (default tests/fuzz/long_run.jsonl) runs
#     until it does or for S seconds (default 1200), whichever comes first, resuming from its kept corpus
#     BUILD_DIR/fuzz-long/<harness>/corpus (outside git; it grows across segments, and the seed corpus
#     BUILD_DIR/fuzz-corpus/<harness> is read with it). The segment is APPENDED to --out as one JSON line
#     per harness: its executions, wall time, coverage at its end (cov/ft, which covers the whole kept
#     corpus, since libFuzzer replays it first), crash inputs written and the outcome. The executions of a
#     harness's segments add up to its total; a segment counts every input libFuzzer executed, the replay
#     of the kept corpus at its start included.
#
# Every run also reads the committed seeds and crash reproducers (tests/fuzz/seeds/<harness>,
# tests/fuzz/regressions/<harness>). BUILD_DIR is a build configured with clang and -DTRAILSCOPE_FUZZ=ON
# whose `fuzzers` target is built. A crash, a sanitizer report, a leak, a timeout (one input running longer
# than --timeout T wall seconds: 10 by default; the long run at nice 19 on a busy machine passes more, since
# a starved fuzzer's input can wait 10 s for a core without being slow) or
# an RSS above 2 GiB is a failure: libFuzzer writes the input to the harness's artifact folder
# (BUILD_DIR/fuzz-artifacts/<harness>/, or BUILD_DIR/fuzz-long/<harness>/artifacts/ in the long run) and the
# script exits non-zero after all harnesses ran.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?usage: run.sh BUILD_DIR (--seconds S | --long [--goal N] [--max-seconds S]) [--timeout T] [--jobs J] [--out FILE] [harness...]}
shift
seconds="" long="" goal=10000000 max_seconds=1200 timeout=10 jobs=1 out="" harnesses=()
while [ $# -gt 0 ]; do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --long) long=1; shift ;;
    --goal) goal=$2; shift 2 ;;
    --max-seconds) max_seconds=$2; shift 2 ;;
    --timeout) timeout=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
[ -n "$seconds$long" ] || { echo "run.sh: give --seconds S or --long" >&2; exit 2; }
[ -n "$seconds" ] && [ -n "$long" ] && { echo "run.sh: --seconds and --long exclude each other" >&2; exit 2; }
if [ ${#harnesses[@]} -eq 0 ]; then
  for f in "$here"/*_fuzz.cpp; do n=$(basename "$f" .cpp); harnesses+=("${n%_fuzz}"); done
fi
for h in "${harnesses[@]}"; do
  [ -x "$build/tests/fuzz/${h}_fuzz" ] || { echo "run.sh: $build/tests/fuzz/${h}_fuzz not built (make fuzz builds it)" >&2; exit 2; }
done
logs=$build/fuzz-logs
mkdir -p "$logs"
if [ -n "$long" ]; then
  out=${out:-$here/long_run.jsonl}
  touch "$out"
else
  out=${out:-$build/fuzz-results.jsonl}
  : > "$out"
fi
commit=$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)

# UBSan aborts on the first report (the code is built with -fno-sanitize-recover too); LSan reports leaks.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}

# Executions and segments already recorded for harness $1 in $out: "EXECUTIONS SEGMENTS".
recorded() {
  python3 - "$out" "$1" <<'PY'
import json, sys
execs = segs = 0
for line in open(sys.argv[1]):
    line = line.strip()
    if line.startswith('{'):
        r = json.loads(line)
        if r.get('harness') == sys.argv[2] and 'segment' in r:
            execs += int(r.get('executions', 0)); segs += 1
print(execs, segs)
PY
}

one() {
  local h=$1 bin="$build/tests/fuzz/${1}_fuzz" log="$logs/$1.log"
  local corpus art dirs limit=() segment="" before=0
  if [ -n "$long" ]; then
    corpus="$build/fuzz-long/$h/corpus" art="$build/fuzz-long/$h/artifacts/"
    local done_execs segs
    read -r done_execs segs < <(recorded "$h")
    if [ "$done_execs" -ge "$goal" ]; then
      printf '%-22s %10s execs in %s segment(s): goal %s reached, skipped\n' "$h" "$done_execs" "$segs" "$goal"
      return 0
    fi
    segment=$((segs + 1))
    limit+=(-runs="$((goal - done_execs))" -max_total_time="$max_seconds")
  else
    corpus="$build/fuzz-corpus/$h" art="$build/fuzz-artifacts/$h/"
    limit+=(-max_total_time="$seconds")
  fi
  mkdir -p "$corpus" "$art"
  # Inputs libFuzzer wrote for a failure (crash-, leak-, timeout-, oom-); its slow-unit- files (an input over
  # 10 s of wall time, a report, not a failure: at nice 19 a starved fuzzer writes them) are not counted.
  before=$(find "$art" -maxdepth 1 -type f ! -name 'slow-unit-*' | wc -l)
  dirs=("$corpus")
  [ -n "$long" ] && [ -d "$build/fuzz-corpus/$h" ] && dirs+=("$build/fuzz-corpus/$h")
  for d in "$here/seeds/$h" "$here/regressions/$h"; do [ -d "$d" ] && dirs+=("$d"); done
  local t0=$SECONDS rc started
  started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
  # CPU seconds (user + system) beside the wall time: at nice 19 on a busy machine the fuzzer gets a small
  # share of a core, and exec/s over the wall time says more about the machine than about the harness.
  local TIMEFORMAT='%U %S' cpu_u cpu_s cpu
  { time "$bin" "${limit[@]}" -timeout="$timeout" -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$art" "${dirs[@]}" > "$log" 2>&1 ; } 2> "$log.cpu"
  rc=$?
  read -r cpu_u cpu_s < "$log.cpu"
  cpu=$(awk -v u="${cpu_u:-0}" -v s="${cpu_s:-0}" 'BEGIN { printf "%.1f", u + s }')
  local wall=$((SECONDS - t0))
  # libFuzzer's final statistics and its last status line ("#N DONE cov: C ft: F corp: K/S ...").
  local execs rate cov ft corp crashes
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -oE ' cov: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  ft=$(grep -oE ' ft: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  corp=$(grep -oE ' corp: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+')
  crashes=$(( $(find "$art" -maxdepth 1 -type f ! -name 'slow-unit-*' | wc -l) - before ))
  local outcome=ok
  [ $rc -ne 0 ] && outcome="failed (exit $rc; see $log and $art)"
  if [ -n "$long" ]; then
    printf '{"bench":"fuzz","harness":"%s","segment":%s,"started":"%s","commit":"%s","max_seconds":%s,"goal":%s,"executions":%s,"exec_per_s":%s,"cov":%s,"ft":%s,"corpus":%s,"wall_s":%s,"cpu_s":%s,"crash_inputs":%s,"exit":%s,"outcome":"%s"}\n' \
      "$h" "$segment" "$started" "$commit" "$max_seconds" "$goal" "${execs:-0}" "${rate:-0}" "${cov:-0}" "${ft:-0}" \
      "${corp:-0}" "$wall" "$cpu" "$crashes" "$rc" "$outcome" >> "$out"
  else
    printf '{"bench":"fuzz","harness":"%s","mode":"seconds=%s","executions":%s,"exec_per_s":%s,"cov":%s,"ft":%s,"corpus":%s,"wall_s":%s,"cpu_s":%s,"crash_inputs":%s,"exit":%s,"outcome":"%s"}\n' \
      "$h" "$seconds" "${execs:-0}" "${rate:-0}" "${cov:-0}" "${ft:-0}" "${corp:-0}" "$wall" "$cpu" "$crashes" "$rc" \
      "$outcome" >> "$out"
  fi
  printf '%-22s %10s execs %7s/s (cpu %6s s) cov %5s ft %6s %s%s\n' "$h" "${execs:-0}" "${rate:-0}" "$cpu" \
    "${cov:-0}" "${ft:-0}" "${segment:+segment $segment: }" "$outcome"
  return $rc
}

failed=0
if [ "$jobs" -le 1 ]; then
  for h in "${harnesses[@]}"; do one "$h" || failed=1; done
else
  export -f one
  export build here seconds long goal max_seconds timeout out logs commit
  export -f recorded
  printf '%s\n' "${harnesses[@]}" | xargs -P "$jobs" -I{} bash -c 'one {}' || failed=1
fi
[ $failed -eq 0 ] || {
  echo "run.sh: a harness failed; the inputs are under $build/${long:+fuzz-long/<harness>/artifacts/}${long:-fuzz-artifacts/}" >&2
  exit 1
}
