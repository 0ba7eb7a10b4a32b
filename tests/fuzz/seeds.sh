#!/usr/bin/env bash
# Builds the fuzzing seed corpus from the real data in the shared folder, out of the tree:
#   tests/fuzz/seeds.sh BUILD_DIR [SHARED]
# writes BUILD_DIR/fuzz-corpus/<harness>/ (the corpus each harness starts from and grows; `make fuzz`
# runs it first). Each seed is a small cut of a real file (a few records, edges or lines), so that the
# fuzzer's mutations stay fast; nothing of the data is copied into the repository. Seeds that need
# TrailScope's own writers (a depth-video pack, tracker logs, stored gaze files) come from the fuzz_seeds
# program. Harnesses with no shared file of their kind (OpenSky CSV, od_csv, the request and control
# messages, the uploaded flow field, the ClickHouse store URL, the AOI body) start from the hand-written
# seeds committed in tests/fuzz/seeds/<harness>/ (run.sh adds them).
set -euo pipefail
build=${1:?usage: seeds.sh BUILD_DIR [SHARED]}
here=$(cd "$(dirname "$0")" && pwd)
shared=${2:-${TRAILSCOPE_SHARED:-$here/../../../shared}}
data=$shared/data
[ -d "$data" ] || { echo "seeds.sh: no data folder at $data (set TRAILSCOPE_SHARED)" >&2; exit 1; }
out=$build/fuzz-corpus
mkdir -p "$out"
seed() { mkdir -p "$out/$1"; cat > "$out/$1/$2"; }

# SO6: the first segments of the Europe day, and segments from the middle of the file.
so6=$data/flights/traffic_europe_20180101_m3.so6.gz
{ zcat "$so6" || true; } | head -n 30 | seed ingest_so6 head30.so6
{ zcat "$so6" || true; } | head -n 200000 | tail -n 12 | seed ingest_so6 mid12.so6

# traffic JSON (arrays of records, gzip) and readsb trace_full: a few records, as an array and as JSON
# Lines; the first trace entries.
python3 - "$data/flights" "$out" <<'PY'
import gzip, json, os, sys
src, out = sys.argv[1], sys.argv[2]
def put(h, name, text):
    os.makedirs(os.path.join(out, h), exist_ok=True)
    open(os.path.join(out, h, name), 'w').write(text)
for f in sorted(os.listdir(src)):
    if f.startswith('traffic_sample_') and f.endswith('.json.gz'):
        recs = json.load(gzip.open(os.path.join(src, f)))[:12]
        base = f[len('traffic_sample_'):-len('.json.gz')]
        put('ingest_traffic_json', base + '.json', json.dumps(recs))
        put('ingest_traffic_json', base + '.jsonl', ''.join(json.dumps(r) + '\n' for r in recs[:6]))
trace = json.load(open(os.path.join(src, 'traffic_sample_trace_full_ac671b.json')))
trace['trace'] = trace['trace'][:12]
put('ingest_readsb_trace', 'ac671b_12.json', json.dumps(trace))
PY

# GraphML (FDEB airlines, migrations): the first edges and only the nodes they use.
python3 - "$data/bundling" "$out/graph_graphml" <<'PY'
import os, re, sys
src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for name in ('airlines', 'migrations'):
    text = open(os.path.join(src, 'classic', name + '.xml')).read()
    head = text[:text.index('<node')]
    edges = re.findall(r'<edge\b.*?(?:/>|</edge>)', text, re.S)[:10]
    used = {m for e in edges for m in re.findall(r'(?:source|target)="([^"]*)"', e)}
    nodes = [n for n in re.findall(r'<node\b.*?(?:/>|</node>)', text, re.S)
             if re.search(r'id="([^"]*)"', n).group(1) in used]
    open(os.path.join(out, name + '.graphml'), 'w').write(
        head + '\n'.join(nodes) + '\n' + '\n'.join(edges) + '\n</graph>\n</graphml>\n')
PY

# node-link JSON (the same graphs, epb): the first links and their nodes.
python3 - "$data/bundling/epb" "$out/graph_node_link" <<'PY'
import json, os, sys
src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for f in sorted(os.listdir(src)):
    g = json.load(open(os.path.join(src, f)))
    key = 'links' if 'links' in g else 'edges'
    links = g[key][:10]
    used = {l['source'] for l in links} | {l['target'] for l in links}
    g['nodes'] = [n for i, n in enumerate(g['nodes']) if n.get('id', i) in used or i in used]
    g[key] = links
    json.dump(g, open(os.path.join(out, f), 'w'))
PY

# CUBu trails: the first lines of .trl / .xy files and of the numbered data sets.
for f in "$data"/bundling/cubu/*; do
  [ -f "$f" ] || continue
  head -n 6 "$f" | cut -c 1-600 | seed graph_trl "$(basename "$f").trl"
done

# MOTChallenge: ground truth, detections and a tracker's output, the first lines of each.
n=0
while IFS= read -r f; do
  n=$((n + 1))
  head -n 25 "$f" | seed mot_text "mot$n.txt"
done < <(find "$data/tracker/mot" -name '*.txt' -path '*gt*' -o -name '*.txt' -path '*tracker_*' | sort)

# Gaze files, every format of the shared gaze folder (gaze_ingest_fuzz.cpp): the header and 20 lines of
# each, the first after the header and 20 from the middle (a line cut at 400 characters), behind the
# harness's first byte: 35 = format detected, both eyes averaged, a 1920 x 1080 px screen given
# (normalised Tobii coordinates need one); 17 = detected, left eye, no screen.
python3 - "$data/gaze" "$out/gaze_ingest" <<'PY'
import glob, os, re, sys
src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
patterns = ['eyelinker_sr_research/mono250.asc', 'eyelinker_sr_research/bino250.asc',
            'i2mc_tobii_tx300/participant1/1.txt', 'gazeparser_tests/*', 'sp_tool_test_data/*',
            'andersson2017_lund/tsv/TL20_img_konijntjes.tsv', 'hooge2018_human_fixation_coding/ETdata/adult_*',
            'pymovements_tests/*', 'pymovements_toy/trial_0_1.csv', 'saccades_luketudge/example.csv']
for pat in patterns:
    for f in sorted(glob.glob(os.path.join(src, pat)))[:4]:
        lines = [l[:400].rstrip(b'\r\n') + b'\n' for l in open(f, 'rb')]
        first = next((i for i, l in enumerate(lines) if re.match(rb'\s*-?[0-9]', l)), len(lines))
        head = lines[:min(first, 300)]
        name = os.path.relpath(f, src).replace('/', '_')
        # The first sample lines, and some from the middle (where a recording that starts with the eye
        # lost has valid samples).
        for cut, body in (('', lines[:min(first, 300) + 20]), ('.mid', head + lines[len(lines) // 2:][:20])):
            text = b''.join(body)
            open(os.path.join(out, name + cut + '.35'), 'wb').write(bytes([35]) + text)
            open(os.path.join(out, name + cut + '.17'), 'wb').write(bytes([17]) + text)
PY

# Depth video: three real depth frames (Open3D's RGB-D sample) cut to 16x12, as single PNGs and through
# fuzz_seeds as a pack and a manifest; tracker logs in both encodings.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/png" "$out/depth_pack"
for i in 0 1 2; do
  oiiotool "$data/tracker/depth_open3d_rgbd/depth/0000$i.png" --resize 16x12 -d uint16 -o "$tmp/png/0000$i.png"
done
cp "$tmp/png/00000.png" "$out/depth_pack/frame16x12.png"
"$build/tests/fuzz/fuzz_seeds" "$tmp/png" "$out"

for d in "$out"/*/; do echo "$(basename "$d"): $(ls "$d" | wc -l) seeds"; done
