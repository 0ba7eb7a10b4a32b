#!/usr/bin/env bash
# `trailscope gaze ingest|events` end to end: real gaze files of the shared data (counts made here with grep
# and awk), a constructed recording with known fixations and saccades, --json, the progress bar, and the exit
# codes and messages of bad input.
# Usage: gaze_cli_test.sh TRAILSCOPE_BIN SHARED_DIR
set -uo pipefail
BIN=$(readlink -f "$1")
GAZE=$(readlink -f "$2")/data/gaze
HERE=$(dirname "${BASH_SOURCE[0]}")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$HERE/../support/cli_checks.sh"

"$BIN" gaze --help > "$TMP/help" 2>&1
check "gaze --help exit" 0 $?
contains "help lists ingest" "ingest" "$TMP/help"
contains "help lists events" "events" "$TMP/help"
"$BIN" gaze events --help > "$TMP/help" 2>&1
contains "events --help names the adaptive method" "Nystrom and Holmqvist 2010" "$TMP/help"

# DSF coord: samples are the rows starting with a digit, valid ones have flag 1.
COORD=$GAZE/sp_tool_test_data/dsf_coord_data_example.coord
"$BIN" gaze ingest "$COORD" --json --quiet > "$TMP/coord.json"
check "ingest coord exit" 0 $?
check "coord samples" "$(grep -c '^[0-9]' "$COORD")" "$(json 'd["files"][0]["samples"]' < "$TMP/coord.json")"
check "coord valid" "$(grep '^[0-9]' "$COORD" | awk '$4 == 1' | wc -l)" \
  "$(json 'd["files"][0]["recordings"][0]["valid_samples"]' < "$TMP/coord.json")"
check "coord format" "dsf_coord" "$(json 'd["files"][0]["recordings"][0]["format"]' < "$TMP/coord.json")"
check "coord distance" "45.0" "$(json 'd["files"][0]["recordings"][0]["geometry"]["distance_cm"]' < "$TMP/coord.json")"

# EyeLink: one recording per START block; two files at once, with the progress bar on stderr.
ASC=$GAZE/saccades_luketudge/example_eyelink_events.txt
"$BIN" gaze ingest "$ASC" "$GAZE/eyelinker_sr_research/bino500.asc" --json > "$TMP/asc.json" 2> "$TMP/asc.err"
check "ingest two files exit" 0 $?
check "asc recordings" "$(grep -c '^START' "$ASC")" "$(json 'len(d["files"][0]["recordings"])' < "$TMP/asc.json")"
check "asc samples" "$(grep -c '^[0-9]' "$ASC")" "$(json 'd["files"][0]["samples"]' < "$TMP/asc.json")"
check "bino500 samples" "$(grep -c '^[0-9]' "$GAZE/eyelinker_sr_research/bino500.asc")" \
  "$(json 'd["files"][1]["samples"]' < "$TMP/asc.json")"
contains "progress bar reaches 100%" "gaze ingest 100%" "$TMP/asc.err"
"$BIN" gaze ingest "$ASC" --quiet > "$TMP/asc.txt"
contains "table names the file" "84 recording(s), 29578 samples, format eyelink_asc" "$TMP/asc.txt"

# A constructed recording in degrees at 500 Hz: fixations at (0,0), (10,0), (10,5), 200 ms each, joined by
# saccades of 40 and 30 ms.
python3 - "$TMP/syn.csv" <<'PY'
import sys
rows, t = [], 0.0
def add(x, y):
    global t
    rows.append(f"{t:.1f},{x:.4f},{y:.4f}"); t += 2.0
def fix(x, y):
    for _ in range(100): add(x, y)
def sac(x0, y0, x1, y1, n):
    for k in range(1, n): add(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n)
fix(0, 0); sac(0, 0, 10, 0, 20); fix(10, 0); sac(10, 0, 10, 5, 15); fix(10, 5)
open(sys.argv[1], "w").write("time,x_deg,y_deg\n" + "\n".join(rows) + "\n")
PY
for m in ivt idt adaptive; do
  "$BIN" gaze events "$TMP/syn.csv" --method $m --json --quiet > "$TMP/ev.json"
  check "events $m exit" 0 $?
  check "events $m fixations" 3 "$(json 'sum(e["type"] == "fixation" for e in d["files"][0]["recordings"][0]["events"])' < "$TMP/ev.json")"
  check "events $m saccades" 2 "$(json 'sum(e["type"] == "saccade" for e in d["files"][0]["recordings"][0]["events"])' < "$TMP/ev.json")"
done
"$BIN" gaze events "$TMP/syn.csv" --quiet > "$TMP/ev.txt"
contains "events table" "3 fixations" "$TMP/ev.txt"

# Bad input: exit 2 with the library's message.
head -n 50 "$COORD" > "$TMP/cut.coord"
printf '999000 768.2' >> "$TMP/cut.coord"  # a file cut in the middle of line 51
"$BIN" gaze ingest "$TMP/cut.coord" --quiet > /dev/null 2> "$TMP/err"
check "truncated exit" 2 $?
contains "truncated message" "trailscope: line 51: coord row has 2 fields, expected at least 4 (truncated?)" "$TMP/err"
"$BIN" gaze events "$TMP/syn.csv" --method fast --quiet > /dev/null 2> "$TMP/err"
check "bad method exit" 2 $?
contains "bad method message" 'method must be ivt, idt or adaptive, not "fast"' "$TMP/err"
"$BIN" gaze events "$TMP/syn.csv" --velocity-threshold 0 --quiet > /dev/null 2> "$TMP/err"
check "bad threshold exit" 2 $?
contains "bad threshold message" "velocity_threshold_deg_s must be in (0, 5000], not 0" "$TMP/err"
"$BIN" gaze events "$ASC" --quiet > /dev/null 2> "$TMP/err"
check "no geometry exit" 2 $?
contains "no geometry message" "degrees of visual angle need the screen size in px and cm" "$TMP/err"
"$BIN" gaze ingest "$TMP/missing.asc" --quiet > /dev/null 2> "$TMP/err"
check "missing file exit" 2 $?
contains "missing file message" "cannot open gaze file $TMP/missing.asc" "$TMP/err"
"$BIN" gaze ingest "$GAZE/andersson2017_lund/stimuli/Europe1024x768.png" --quiet > /dev/null 2> "$TMP/err"
check "image exit" 2 $?
contains "image message" "binary data, not a gaze text file" "$TMP/err"
"$BIN" gaze ingest "$COORD" --format nope --quiet > /dev/null 2> "$TMP/err"
check "bad format exit" 2 $?
contains "bad format message" 'unknown gaze format "nope"' "$TMP/err"
# Storing into a data folder: --name --data-dir, then list and delete; the counts made here with grep.
DATA=$TMP/data
MONO=$GAZE/eyelinker_sr_research/mono500.asc
"$BIN" gaze ingest "$MONO" --name mono --data-dir "$DATA" --json --quiet > "$TMP/store.json"
check "store ingest exit" 0 $?
check "stored recordings" "$(grep -c '^START' "$MONO")" "$(json 'd["recordings"]' < "$TMP/store.json")"
check "stored samples" "$(grep -c '^[0-9]' "$MONO")" "$(json 'd["samples"]' < "$TMP/store.json")"
test -f "$DATA/gaze/mono/recordings.tsgz" && test -f "$DATA/gaze/mono/manifest.json"
check "stored files" 0 $?
"$BIN" gaze list --data-dir "$DATA" --json > "$TMP/list.json"
check "list ids" "['mono']" "$(json '[x["id"] for x in d["datasets"]]' < "$TMP/list.json")"
check "list samples" "$(grep -c '^[0-9]' "$MONO")" "$(json 'd["datasets"][0]["samples"]' < "$TMP/list.json")"
"$BIN" gaze ingest "$MONO" --name mono --data-dir "$DATA" --quiet > /dev/null 2> "$TMP/err"
check "taken name exit" 2 $?
contains "taken name message" "trailscope: gaze dataset 'mono' already exists" "$TMP/err"
"$BIN" gaze ingest "$MONO" --name "Bad Name" --data-dir "$DATA" --quiet > /dev/null 2> "$TMP/err"
check "bad name exit" 2 $?
"$BIN" gaze ingest "$TMP/cut.coord" --name cut --data-dir "$DATA" --quiet > /dev/null 2> "$TMP/err"
check "damaged store exit" 2 $?
contains "damaged store message" "line 51: coord row has 2 fields, expected at least 4 (truncated?)" "$TMP/err"
test ! -e "$DATA/gaze/cut"
check "damaged file stored nothing" 0 $?
# Killed mid-write (every sample written, the manifest not yet): nothing listed, nothing in gaze/.
TRAILSCOPE_FAILPOINT=store.write.before_manifest "$BIN" gaze ingest "$MONO" --name killed --data-dir "$DATA" \
  --quiet > /dev/null 2> "$TMP/err"
check "killed exit" 137 $?
contains "killed at the failpoint" "failpoint store.write.before_manifest: SIGKILL" "$TMP/err"
test ! -e "$DATA/gaze/killed"
check "killed write left no dataset" 0 $?
check "killed write's staging folder is in tmp/ (a CLI keeps it; the server removes it at start)" 1 \
  "$(ls "$DATA/tmp" | grep -c '^gaze\.killed\.')"
check "killed write not listed" "['mono']" "$("$BIN" gaze list --data-dir "$DATA" --json | json '[x["id"] for x in d["datasets"]]')"
TRAILSCOPE_FAILPOINT=store.publish.after_rename "$BIN" gaze ingest "$MONO" --name whole --data-dir "$DATA" \
  --quiet > /dev/null 2> "$TMP/err"
check "killed after rename exit" 137 $?
check "renamed dataset is whole" "['mono', 'whole']" \
  "$("$BIN" gaze list --data-dir "$DATA" --json | json '[x["id"] for x in d["datasets"]]')"
"$BIN" gaze delete whole --data-dir "$DATA" > "$TMP/out"
check "delete exit" 0 $?
contains "delete message" "deleted gaze dataset 'whole'" "$TMP/out"
"$BIN" gaze delete whole --data-dir "$DATA" > /dev/null 2> "$TMP/err"
check "delete again exit" 2 $?
contains "delete again message" "gaze dataset 'whole' does not exist" "$TMP/err"
"$BIN" gaze list --data-dir "$DATA" > "$TMP/out"
contains "list table" "mono: $(grep -c '^START' "$MONO") recording(s), $(grep -c '^[0-9]' "$MONO") samples, eyelink_asc" "$TMP/out"
finish
