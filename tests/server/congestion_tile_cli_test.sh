#!/usr/bin/env bash
# `trailscope tile --congestion` end to end: a small OpenSky CSV ingested into a scratch store, the
# congestion tile at an instant and over a window (JSON report and PNG), and the exit codes and messages
# of bad input. Usage: congestion_tile_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"

# Two aircraft hover over (52.3, 4.76) for 10 minutes; a third passes far away.
cat > "$TMP/c.csv" <<'CSV'
time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude
1514764800,4ca1d0,52.3,4.76,0,0,0,KLM1,false,3000
1514765400,4ca1d0,52.3,4.76,0,0,0,KLM1,false,3000
1514764800,4ca1d1,52.3,4.76,0,0,0,KLM2,false,3500
1514765400,4ca1d1,52.3,4.76,0,0,0,KLM2,false,3500
1514764800,3c6444,50,8,200,0,0,DLH3,false,9000
1514765400,3c6444,51,8,200,0,0,DLH3,false,9000
CSV
"$BIN" ingest "$TMP/c.csv" --name c --data-dir "$TMP/data" --quiet > /dev/null
check "ingest exit" 0 $?
tile() { "$BIN" tile c 6 32 21 -o "$TMP/t.png" --data-dir "$TMP/data" --congestion "$@"; }

tile --t 2018-01-01T00:05:00Z --threshold 2 --json > "$TMP/t.json"
check "instant exit" 0 $?
check "instant: one pixel of two aircraft" "1 2.0" "$(json 'd["pixels_above"], d["max_value"]' < "$TMP/t.json" | tr -d '(),')"
check "png magic" "89504e47" "$(head -c 4 "$TMP/t.png" | od -An -tx1 | tr -d ' \n')"
tile --t0 1514764800 --t1 1514766000 --threshold 0.5 --json > "$TMP/w.json"
check "window exit" 0 $?
check "window: a mean of one aircraft" "1 1.0" "$(json 'd["pixels_above"], d["max_value"]' < "$TMP/w.json" | tr -d '(),')"
tile --t 1514765100 > "$TMP/t.txt"
contains "text report" "pixels at or above 1 aircraft" "$TMP/t.txt"

tile 2> "$TMP/err" > /dev/null
check "no instant nor window exits 2" 2 $?
check "no instant nor window named" "trailscope: t0: give the instant t, or the window t0 and t1" "$(cat "$TMP/err")"
tile --t 1514765100 --threshold 0 2> "$TMP/err" > /dev/null
check "threshold exits 2" 2 $?
check "threshold named" "trailscope: threshold: must be a finite number of aircraft > 0" "$(cat "$TMP/err")"
tile --t 1514765100 --kernel 2 2> "$TMP/err" > /dev/null
check "kernel exits 2" 2 $?
check "kernel refused" "trailscope: --kernel does not apply to --congestion" "$(cat "$TMP/err")"
"$BIN" tile c 6 32 21 -o "$TMP/d.png" --data-dir "$TMP/data" --t 1514765100 2> "$TMP/err" > /dev/null
check "--t without --congestion exits 2" 2 $?
check "--t without --congestion named" "trailscope: --t applies to --congestion only" "$(cat "$TMP/err")"
finish
