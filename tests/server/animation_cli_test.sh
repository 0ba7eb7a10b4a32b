#!/usr/bin/env bash
# `trailscope query animation` end to end: a small OpenSky CSV ingested into a scratch store, one chunk as
# TSAN bytes (decoded here with Python's struct, from the layout of proto/animation_chunks.md), as JSON and
# as a summary line, and the exit codes and messages of bad input.
# Usage: animation_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"

# KLM1 flies (52, 4) → (53, 6) over 00:00–00:10 with a sample at 00:05:30; DLH2 stands at (50, 8) from
# 00:00 to 00:20. The chunk [00:05, 00:10) holds KLM1's samples at 00:00 (before), 00:05:30 and 00:10
# (after), and DLH2's at 00:00 and 00:20 (one leg over the whole chunk).
cat > "$TMP/pos.csv" <<'CSV'
time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,baroaltitude
1514764800,4ca1d0,52,4,200,350,2,KLM1,false,1000
1514765130,4ca1d0,52.5,5,210,0,2,KLM1,false,1500
1514765400,4ca1d0,53,6,220,10,,KLM1,false,2000
1514764800,3c6444,50,8,0,0,0,DLH2,true,100
1514766000,3c6444,50,8,0,0,0,DLH2,true,100
CSV
"$BIN" ingest "$TMP/pos.csv" --name pos --data-dir "$TMP/data" --quiet > /dev/null
check "ingest exit" 0 $?
q() { "$BIN" query animation pos --data-dir "$TMP/data" "$@"; }

q --t 2018-01-01T00:05:00Z --json > "$TMP/a.json"
check "json exit" 0 $?
check "json flights, samples" "2 5" "$(json '"%d %d" % (d["count"], d["samples"])' < "$TMP/a.json")"
check "json chunk" "1514765100.0 300.0 pos" "$(json '"%s %s %s" % (d["t"], d["duration"], d["dataset"])' < "$TMP/a.json")"
check "json origin: the dataset's centre" "[6.0, 51.5]" "$(json 'd["origin"]' < "$TMP/a.json")"
check "json KLM1 samples (absolute times)" "[1514764800.0, 1514765130.0, 1514765400.0]" \
  "$(json '[s["t"] for f in d["flights"] if f["callsign"] == "KLM1" for s in f["samples"]]' < "$TMP/a.json")"
check "json DLH2 brackets" "[1514764800.0, 1514766000.0] True" \
  "$(json '" ".join(str(x) for f in d["flights"] if f["callsign"] == "DLH2" for x in ([s["t"] for s in f["samples"]], f["samples"][0]["on_ground"]))' < "$TMP/a.json")"
check "json unknown vrate is null" "None" \
  "$(json '[f for f in d["flights"] if f["callsign"] == "KLM1"][0]["samples"][2]["vrate_ms"]' < "$TMP/a.json")"

q --t 1514765100 --out "$TMP/a.tsan" > "$TMP/a.txt"
check "tsan exit" 0 $?
contains "summary line" "2 flights, 5 samples in 2018-01-01T00:05:00Z .. 2018-01-01T00:10:00Z" "$TMP/a.txt"
cat > "$TMP/decode.py" <<'PY'
import math, struct, sys
b = open(sys.argv[1], "rb").read()
magic, ver, flags, t0, dur, ox, oy, nf, ns, sb = struct.unpack_from("<4sHHddddIII", b, 0)
pad = lambda n: (n + 7) // 8 * 8
C = pad(4 * ns)
cols = 64 + 24 * nf
strings = cols + 7 * C + pad(ns)
assert len(b) == strings + pad(sb), (len(b), strings + pad(sb))
col = lambda k: struct.unpack_from("<%df" % ns, b, cols + k * C)
t, x, y = col(0), col(1), col(2)
R = 6378137.0
out = [magic.decode(), str(ver), "%.0f" % t0, "%.0f" % dur]
for i in range(nf):
    fid, first, count, icao, off, ln = struct.unpack_from("<6I", b, 64 + 24 * i)
    cs = b[strings + off: strings + off + ln].decode()
    lats = ["%.4f" % math.degrees(math.atan(math.sinh((y[k] + oy) / R))) for k in range(first, first + count)]
    lons = ["%.4f" % math.degrees((x[k] + ox) / R) for k in range(first, first + count)]
    out.append("%s:%06x:%s:%s:%s" % (cs, icao, ",".join("%g" % t[k] for k in range(first, first + count)),
                                     ",".join(lats), ",".join(lons)))
print(" ".join(out))
PY
check "tsan decoded" \
  "TSAN 1 1514765100 300 DLH2:3c6444:-300,900:50.0000,50.0000:8.0000,8.0000 KLM1:4ca1d0:-300,30,300:52.0000,52.5000,53.0000:4.0000,5.0000,6.0000" \
  "$(python3 "$TMP/decode.py" "$TMP/a.tsan")"
check "callsign filter" "1 KLM1" \
  "$(q --t 1514765100 --callsign klm --json | json '"%d %s" % (d["count"], d["flights"][0]["callsign"])')"
check "next chunk: KLM1 ended at its start" "KLM1,DLH2" \
  "$(q --t 1514765400 --json | json '",".join(sorted((f["callsign"] for f in d["flights"]), reverse=True))')"
check "after everything" 0 "$(q --t 2018-01-01T01:00:00Z --json | json 'd["count"]')"

q --t 1514765101 2> "$TMP/err" > /dev/null
check "misaligned t exits 2" 2 $?
check "misaligned t message" \
  "trailscope: t: chunks start at multiples of duration=300; the nearest starts are 1514765100 and 1514765400" \
  "$(cat "$TMP/err")"
q --t 1514765100 --duration 5 2> "$TMP/err" > /dev/null
check "short duration exits 2" 2 $?
check "short duration message" "trailscope: duration must be in [10, 3600] seconds" "$(cat "$TMP/err")"
q --t 1514765100 --bbox 0,40,10,60 2> "$TMP/err" > /dev/null
check "bbox exits 2" 2 $?
check "bbox refused" \
  "trailscope: bbox does not apply to animation chunks: the player filters positions during playback, and the chunk is the time window" \
  "$(cat "$TMP/err")"
"$BIN" query animation nope --data-dir "$TMP/data" --t 1514765100 2> "$TMP/err" > /dev/null
check "unknown dataset exits 2" 2 $?
q 2> "$TMP/err" > /dev/null
rc=$?
check "missing --t fails" 1 "$([ $rc -ne 0 ] && echo 1 || echo 0)"
"$BIN" query animation --help > "$TMP/help.txt"
contains "help names --duration" "--duration" "$TMP/help.txt"
contains "help names --out" "--out" "$TMP/help.txt"

finish
