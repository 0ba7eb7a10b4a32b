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
# The views (gaze tile|aoi|bundle) on a Lund recording of the Europe image, checked against sums made here
# from the raw TSV (time_us, pupil, pupil, x_px, y_px, ...; x = y = 0 is a lost sample).
LUND=$GAZE/andersson2017_lund/tsv/UH29_img_Europe.tsv
GEO="--width-px 1024 --height-px 768 --width-cm 38 --height-cm 30 --distance-cm 67"
for v in tile aoi bundle; do
  "$BIN" gaze $v --help > "$TMP/help" 2>&1
  check "gaze $v --help exit" 0 $?
done
"$BIN" gaze tile --help > "$TMP/help" 2>&1
contains "tile --help explains the grid" "2^z x 2^z tiles" "$TMP/help"
"$BIN" gaze aoi --help > "$TMP/help" 2>&1
contains "aoi --help states the overlap rule" "first AOI" "$TMP/help"
"$BIN" gaze bundle --help > "$TMP/help" 2>&1
contains "bundle --help lists the bundling flags" "--iterations" "$TMP/help"
"$BIN" gaze tile "$LUND" $GEO -o "$TMP/t.png" --z 0 --x 0 --y 0 --how linear --json --quiet > "$TMP/tile.json"
check "tile exit" 0 $?
check "tile is a PNG" "89504e47" "$(head -c 4 "$TMP/t.png" | od -An -tx1 | tr -d ' \n')"
check "tile points = valid samples" "$(awk 'NR > 1 && !($4 == 0 && $5 == 0)' "$LUND" | wc -l)" \
  "$(json 'd["points"]' < "$TMP/tile.json")"
check "tile legend top = the fullest 4 px cell" "$(python3 - "$LUND" <<'PY'
import sys, collections
c = collections.Counter()
for line in list(open(sys.argv[1]))[1:]:
    f = line.split(); x, y = float(f[3]), float(f[4])
    if not (x == 0 and y == 0) and 0 <= x < 1024 and 0 <= y < 768: c[(int(x // 4), int(y // 4))] += 1
print(float(max(c.values())))
PY
)" "$(json 'd["legend"]["hi"]' < "$TMP/tile.json")"
"$BIN" gaze tile "$LUND" $GEO -o "$TMP/f.png" --z 1 --x 1 --y 0 --what fixations --kernel-radius 4 --quiet > "$TMP/tile.txt"
check "fixation tile exit" 0 $?
contains "tile text" "tile 1/1/0 of a 1024x768 px stimulus" "$TMP/tile.txt"

# AOIs: the fixations of `gaze events`, their centroids computed here from the samples, counted per AOI.
"$BIN" gaze events "$LUND" $GEO --json --quiet > "$TMP/lev.json"
"$BIN" gaze aoi "$LUND" $GEO --aoi left:0,0,512,768 --aoi 'tri:512,0,1024,0,1024,768' --json --quiet > "$TMP/aoi.json"
check "aoi exit" 0 $?
python3 - "$LUND" "$TMP/lev.json" > "$TMP/aoi_want" <<'PY'
import sys, json
rows = [l.split() for l in list(open(sys.argv[1]))[1:]]
t = [float(r[0]) / 1000 for r in rows]
ev = json.load(open(sys.argv[2]))["files"][0]["recordings"][0]["events"]
fix = [e for e in ev if e["type"] == "fixation"]
left = tri = out = 0
for e in fix:
    pts = [(float(r[3]), float(r[4])) for r, tt in zip(rows, t) if e["t_start_ms"] <= tt <= e["t_end_ms"]]
    x = sum(p[0] for p in pts) / len(pts); y = sum(p[1] for p in pts) / len(pts)
    if 0 <= x <= 512 and 0 <= y <= 768: left += 1
    elif x <= 1024 and y >= 0 and y <= 1.5 * (x - 512): tri += 1
    else: out += 1
print(len(fix), left, tri, out)
PY
check "aoi counts (fixations left tri outside)" "$(cat "$TMP/aoi_want")" \
  "$(json 'd["fixations"], d["aois"][0]["fixations"], d["aois"][1]["fixations"], d["outside"]' < "$TMP/aoi.json" | tr -d '(),')"
check "aoi transitions add up" \
  "$(json 'd["aois"][0]["fixations"] + d["aois"][1]["fixations"] - 1' < "$TMP/aoi.json")" \
  "$(json 'sum(sum(r) for r in d["transitions"]["counts"])' < "$TMP/aoi.json")"
echo '{"aois": [{"name": "all", "rect": [0, 0, 1024, 768]}]}' > "$TMP/aois.json"
"$BIN" gaze aoi "$LUND" $GEO --aoi-file "$TMP/aois.json" --quiet > "$TMP/aoi.txt"
check "aoi file exit" 0 $?
contains "aoi table" "transitions (row: from, column: to)" "$TMP/aoi.txt"

# Saccade bundling: every saccade of `gaze events` is one bundled line.
"$BIN" gaze bundle "$LUND" $GEO -o "$TMP/b.png" --size 128 --iterations 4 --width 256 --backend cpu --json --quiet > "$TMP/b.json"
check "bundle exit" 0 $?
check "bundle saccades" "$(json 'sum(e["type"] == "saccade" for e in d["files"][0]["recordings"][0]["events"])' < "$TMP/lev.json")" \
  "$(json 'd["source"]["saccades"]' < "$TMP/b.json")"
check "bundle units" "plane" "$(json 'd["units"]' < "$TMP/b.json")"
check "bundle image is a PNG" "89504e47" "$(head -c 4 "$TMP/b.png" | od -An -tx1 | tr -d ' \n')"

# Bad input of the views.
"$BIN" gaze tile "$LUND" $GEO -o "$TMP/x.png" --z 0 --x 5 --quiet > /dev/null 2> "$TMP/err"
check "tile bad x exit" 2 $?
contains "tile bad x message" "tile column 5 is outside 0..0 at zoom 0" "$TMP/err"
"$BIN" gaze tile "$LUND" -o "$TMP/x.png" --what pixels --quiet > /dev/null 2> "$TMP/err"
check "tile bad what exit" 2 $?
contains "tile bad what message" "'pixels' is not samples or fixations" "$TMP/err"
"$BIN" gaze tile "$LUND" -o "$TMP/x.png" --quiet > /dev/null 2> "$TMP/err"
check "tile no size exit" 2 $?
contains "tile no size message" "recording 0 gives no screen size in px (width_px, height_px)" "$TMP/err"
"$BIN" gaze aoi "$LUND" $GEO --quiet > /dev/null 2> "$TMP/err"
check "aoi none exit" 2 $?
contains "aoi none message" "give at least one --aoi or an --aoi-file" "$TMP/err"
"$BIN" gaze aoi "$LUND" $GEO --aoi a:1,2,3 --quiet > /dev/null 2> "$TMP/err"
check "aoi bad spec exit" 2 $?
contains "aoi bad spec message" "4 numbers (a rectangle) or 3 or more x,y pairs (a polygon)" "$TMP/err"
"$BIN" gaze aoi "$LUND" $GEO --aoi a:0,0,1,1 --aoi a:0,0,2,2 --quiet > /dev/null 2> "$TMP/err"
check "aoi twice exit" 2 $?
contains "aoi twice message" "AOI 1 (a): name used twice" "$TMP/err"
"$BIN" gaze bundle "$LUND" $GEO -o "$TMP/x.png" --t0-ms 100000000 --quiet > /dev/null 2> "$TMP/err"
check "bundle empty exit" 2 $?
contains "bundle empty message" "no saccade to bundle in the selected recordings" "$TMP/err"
finish
