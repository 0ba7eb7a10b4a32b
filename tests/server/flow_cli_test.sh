#!/usr/bin/env bash
# `trailscope flow` end to end: a small CSV of crossing traffic ingested into a scratch store, the PNG and
# the JSON, the level, an uploaded field, and the exit codes and messages of bad input.
# Usage: flow_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"

# Thirty flights east along 48..48.75°N and thirty west just south of them, a sample a minute.
python3 - "$TMP/flow.csv" <<'PY'
import sys
with open(sys.argv[1], "w") as f:
    f.write("time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude\n")
    for n in range(60):
        for k in range(41):
            east = n < 30
            lat = 48 + 0.025 * (n % 30) - (0 if east else 0.01)
            lon = 0.25 * k if east else 10 - 0.25 * k
            f.write(f"{1514764800 + 60 * (n + k)},{0x300000 + n:06x},{lat:.4f},{lon:.4f},230,{90 if east else 270},0,"
                    f"FLW{n},false,10000\n")
PY
"$BIN" ingest "$TMP/flow.csv" --name fl --data-dir "$TMP/data" --quiet > /dev/null
check "ingest exit" 0 $?
f() { "$BIN" flow fl --data-dir "$TMP/data" --quiet "$@"; }

f -o "$TMP/a.png" --param grid=64 --json > "$TMP/a.json"
check "png+json exit" 0 $?
check "png signature" "89504e47" "$(head -c 4 "$TMP/a.png" | od -An -tx1 | tr -d ' \n')"
check "json size matches the png" "$(json 'str(d["width"]) + "x" + str(d["height"])' < "$TMP/a.json")" \
  "$(python3 -c "import struct,sys; b=open(sys.argv[1],'rb').read(24); print('%dx%d' % struct.unpack('>II', b[16:24]))" "$TMP/a.png")"
check "east and west flows both traced" "True True" \
  "$(json '" ".join(str(any(l["sector"] == s for l in d["lines"])) for s in (2, 6))' < "$TMP/a.json")"
check "level defaults to 2" 2.0 "$(json 'float(d["level"])' < "$TMP/a.json")"
check "points are lon/lat in the data" True \
  "$(json 'all(-0.5 <= p[0] <= 10.5 and 47.5 <= p[1] <= 50 for l in d["lines"] for p in l["points"])' < "$TMP/a.json")"

f -o "$TMP/b.png" --param grid=64 --level 1 > "$TMP/b.txt"
check "text exit" 0 $?
contains "text names the level" "level 1" "$TMP/b.txt"
check "levels differ" 1 "$(cmp -s "$TMP/a.png" "$TMP/b.png" && echo 0 || echo 1)"

f -o "$TMP/c.png" --param grid=64 --bbox 2,47,8,50 --t0 1514766000 --t1 1514770000 --json > "$TMP/c.json"
check "window exit" 0 $?
check "window grid from the bbox" True "$(json 'abs(d["grid"]["x0"] - (2 + 180) / 360 * 2**32) < 2' < "$TMP/c.json")"

# An uploaded field through the same path: a uniform flow to the east.
python3 -c "
import json; w, h = 20, 12
print(json.dumps({'format': 'trailscope-flow-field', 'version': 1, 'width': w, 'height': h, 'u': [1] * (w * h), 'v': [0] * (w * h)}))" > "$TMP/field.json"
"$BIN" flow --field "$TMP/field.json" --quiet --param min_traffic=0.5 --param d_sep=2 --level 1 --json > "$TMP/f.json"
check "field exit" 0 $?
check "field lines run east at constant y" True \
  "$(json 'all(p[1] == l["points"][0][1] for l in d["lines"] for p in l["points"]) and len(d["lines"]) >= 4' < "$TMP/f.json")"

f -o "$TMP/x.png" --level 3 2> "$TMP/err" > /dev/null
check "bad level exits 2" 2 $?
check "bad level message" "trailscope: level must be in [0, 2]" "$(cat "$TMP/err")"
f -o "$TMP/x.png" --param colour=red 2> "$TMP/err" > /dev/null
check "unknown param exits 2" 2 $?
check "unknown param message" "trailscope: unknown flow parameter 'colour'" "$(cat "$TMP/err")"
f -o "$TMP/x.png" --param grid 2> "$TMP/err" > /dev/null
check "param without = exits 2" 2 $?
check "param without = message" "trailscope: --param takes NAME=VALUE, got 'grid'" "$(cat "$TMP/err")"
f -o "$TMP/x.png" --param grid=1024 --param d_sep=0.5 --param step=0.05 --param sectors=16 2> "$TMP/err" > /dev/null
check "cost refused exits 2" 2 $?
contains "cost refused names the limit" "limits::kMaxFlowLinePoints" "$TMP/err"
f -o "$TMP/x.png" --callsign NOPE 2> "$TMP/err" > /dev/null
check "no flight exits 2" 2 $?
check "no flight message" "trailscope: no flight matches the query" "$(cat "$TMP/err")"
"$BIN" flow nope --data-dir "$TMP/data" -o "$TMP/x.png" 2> "$TMP/err" > /dev/null
check "unknown dataset exits 2" 2 $?
check "unknown dataset message" "trailscope: dataset 'nope' does not exist" "$(cat "$TMP/err")"
"$BIN" flow --field "$TMP/none.json" -o "$TMP/x.png" 2> "$TMP/err" > /dev/null
check "missing field file exits 2" 2 $?
echo '{"format": "trailscope-flow-field", "version": 1, "width": 1}' > "$TMP/bad.json"
"$BIN" flow --field "$TMP/bad.json" -o "$TMP/x.png" 2> "$TMP/err" > /dev/null
check "bad field exits 2" 2 $?
check "bad field message" "trailscope: width must be 2..1024 cells (limits::kMaxFlowGridCells)" "$(cat "$TMP/err")"
f 2> "$TMP/err" > /dev/null
check "no output exits 2" 2 $?
check "no output message" "trailscope: output: give -o OUT.png and/or --json" "$(cat "$TMP/err")"

finish
