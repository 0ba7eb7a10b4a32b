#!/usr/bin/env bash
# `trailscope track` end to end: a synthetic video in, a log out in both encodings, the summary, and the
# exit codes and messages of bad input.
# Usage: track_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../../support/cli_checks.sh"

"$BIN" synth --frames 40 --seed 3 -o "$TMP/clip" > /dev/null 2>&1
check "synth exit" 0 $?

"$BIN" track "$TMP/clip" -o "$TMP/run.json" --ncc-min 0.6 --frames 30 --first 5 --run-id run-cli --json \
  > "$TMP/summary.json" 2> "$TMP/err"
check "track exit" 0 $?
check "summary frames" 30 "$(json 'd["frames"]' < "$TMP/summary.json")"
check "summary first frame" 5 "$(json 'd["first_frame"]' < "$TMP/summary.json")"
check "summary run id" run-cli "$(json 'd["run_id"]' < "$TMP/summary.json")"
check "summary state counts add up" 30 "$(json 'sum(d["states"].values())' < "$TMP/summary.json")"
check "summary fps positive" True "$(json 'd["fps"] > 0' < "$TMP/summary.json")"
check "summary accuracy frames" 30 "$(json 'd["accuracy"]["frames"]' < "$TMP/summary.json")"
check "log is protobuf JSON" "30 5 0.6 run-cli" "$(json '" ".join(map(str, [d["header"]["frameCount"], d["frames"][0]["index"], [p["value"] for p in d["header"]["params"] if p["name"] == "ncc_min"][0], d["header"]["runId"]]))' < "$TMP/run.json")"
check "log has truth per frame" 30 "$(json 'len(d["truth"])' < "$TMP/run.json")"

"$BIN" track "$TMP/clip" -o "$TMP/run.tslog" --quiet > "$TMP/out.txt" 2>&1
check "binary track exit" 0 $?
contains "text summary" "tracked 40 frames of clip" "$TMP/out.txt"
check "binary log is not JSON" no "$(head -c 1 "$TMP/run.tslog" | grep -q '{' && echo yes || echo no)"

"$BIN" track "$TMP/clip" -o "$TMP/run.tslog" --quiet > /dev/null 2> "$TMP/err"
check "existing output exit" 2 $?
contains "existing output message" "exists (--force replaces it)" "$TMP/err"
"$BIN" track "$TMP/clip" -o "$TMP/run.tslog" --quiet --force > /dev/null 2>&1
check "--force exit" 0 $?

"$BIN" track "$TMP/clip" -o "$TMP/bad.json" --ncc-min 2 > /dev/null 2> "$TMP/err"
check "out-of-range value exit" 2 $?
# The wording after the flag is the parameter table's; the flag must come first, once.
check "out-of-range value names the flag" "trailscope: --ncc-min: ncc_min" "$(head -c 30 "$TMP/err")"
"$BIN" track "$TMP/clip" -o "$TMP/bad.json" --templates abc > /dev/null 2> "$TMP/err"
check "non-number exit" 2 $?
check "non-number names the flag once" "trailscope: --templates: 'abc' is not a number" "$(cat "$TMP/err")"
"$BIN" track "$TMP/clip" -o "$TMP/bad.json" --r-min-mm 20 --r-max-mm 10 > /dev/null 2> "$TMP/err"
check "cross-constraint exit" 2 $?
contains "cross-constraint names the flag" "--r-max-mm:" "$TMP/err"
"$BIN" track "$TMP/clip" -o "$TMP/bad.json" --first 40 > /dev/null 2> "$TMP/err"
check "frame range exit" 2 $?
contains "frame range names the flag" "--first:" "$TMP/err"
check "nothing written on errors" no "$([ -e "$TMP/bad.json" ] && echo yes || echo no)"

"$BIN" track --help > "$TMP/help" 2>&1
for flag in --a-min --z-min-mm --median-k --ncc-min --kalman-q --kalman-r-mm --min-teats; do
  contains "--help lists $flag" "$flag" "$TMP/help"
done
contains "--help shows unit, range and default" "[mm, 0..5000, default 80]" "$TMP/help"

# `trailscope compare`: the two logs above share frames 5..34 and differ in ncc_min.
"$BIN" compare "$TMP/run.json" "$TMP/run.tslog" --json --top 3 > "$TMP/cmp.json" 2> "$TMP/err"
check "compare exit" 0 $?
check "compare shared range" "5 30" "$(json '" ".join(map(str, [d["first_frame"], d["frames"]]))' < "$TMP/cmp.json")"
check "compare series per run" "30 30" "$(json '" ".join(str(len(s["state"])) for s in d["series"])' < "$TMP/cmp.json")"
check "compare differing parameter first" "ncc_min True [0.6, 0.25]" "$(json '" ".join(map(str, [d["params"][0]["name"], d["params"][0]["differs"], d["params"][0]["values"]]))' < "$TMP/cmp.json")"
check "compare top" True "$(json 'len(d["disagreements"]) <= 3' < "$TMP/cmp.json")"
"$BIN" compare "$TMP/run.tslog" > "$TMP/out.txt" 2> "$TMP/err"
check "compare one run exit" 2 $?
check "compare one run message" "trailscope: runs: compare 2 to 8 runs, got 1" "$(cat "$TMP/err")"
"$BIN" compare "$TMP/run.tslog" "$TMP/run.json" > "$TMP/out.txt" 2>&1
check "compare text exit" 0 $?
contains "compare text names the video" "2 runs of video 'clip', frames 5..34" "$TMP/out.txt"
contains "compare text marks the differing parameter" "* ncc_min" "$TMP/out.txt"

finish
