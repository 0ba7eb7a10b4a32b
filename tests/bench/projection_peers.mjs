// The npm projection peers on the data projection_bench wrote (standardised float32, row-major):
// @saehrimnir/druidjs (PCA, classical MDS, exact t-SNE), umap-js (UMAP) and tsne-js (exact t-SNE), each
// in its own Node process with a time budget. Prints one JSON line per run:
//   {"peer","version","method","n","dims","ms","params","coords":[x0,y0,x1,y1,...]}  or  {..., "skipped": why}
// projection_bench --score-peers scores the coordinates with TrailScope's own quality code, so every
// layout is measured the same way. Timings cover the library call only (not reading the file).
//
//   node tests/bench/projection_peers.mjs --data-dir DIR [--sizes 1000,5000] [--dims 50] [--budget-s 120]
//
// Packages: tests/bench/peers (npm ci there). Parameters: t-SNE perplexity 30 and 1000 iterations as
// TrailScope's run (each library's own learning rate and exaggeration); UMAP with its defaults.
import { spawnSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const peers = join(here, "peers");
const require = createRequire(join(peers, "package.json"));

function args(argv) {
  const a = {};
  for (let i = 0; i < argv.length; ++i) {
    if (!argv[i].startsWith("--")) continue;
    const k = argv[i].slice(2);
    a[k] = i + 1 < argv.length && !argv[i + 1].startsWith("--") ? argv[++i] : "1";
  }
  return a;
}

function version(pkg) {
  return JSON.parse(readFileSync(join(peers, "node_modules", pkg, "package.json"), "utf8")).version;
}

function load(dir, n, dims) {
  const buf = readFileSync(join(dir, `proj_${n}x${dims}.f32`));
  const f = new Float32Array(buf.buffer, buf.byteOffset, n * dims);
  const rows = new Array(n);
  for (let i = 0; i < n; ++i) rows[i] = Array.from(f.subarray(i * dims, (i + 1) * dims));
  return rows;
}

// A seeded generator for umap-js (mulberry32), so that runs repeat.
function mulberry32(seed) {
  return () => {
    seed |= 0;
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// The line of a child's stderr that says what went wrong (Node ends it with its version line).
function errorLine(text) {
  const lines = text.trim().split("\n");
  return lines.find((l) => /Error/.test(l)) || lines[lines.length - 1];
}

const RUNS = [
  { peer: "@saehrimnir/druidjs", method: "pca" },
  { peer: "@saehrimnir/druidjs", method: "mds" },
  { peer: "@saehrimnir/druidjs", method: "tsne" },
  { peer: "umap-js", method: "umap" },
  { peer: "tsne-js", method: "tsne" },
];

async function runOne(peer, method, X) {
  const toArray = (Y) => (Array.isArray(Y) ? Y : Y.to2dArray ? Y.to2dArray() : Array.from(Y));
  if (peer === "@saehrimnir/druidjs") {
    const druid = await import(require.resolve("@saehrimnir/druidjs"));
    if (method === "pca") return { params: { d: 2 }, run: () => toArray(new druid.PCA(X, { d: 2 }).transform()) };
    if (method === "mds") return { params: { d: 2 }, run: () => toArray(new druid.MDS(X, { d: 2 }).transform()) };
    const p = { perplexity: 30, d: 2, seed: 42, iterations: 1000 };
    return { params: p, run: () => toArray(new druid.TSNE(X, { perplexity: 30, d: 2, seed: 42 }).transform(1000)) };
  }
  if (peer === "umap-js") {
    const { UMAP } = await import(require.resolve("umap-js"));
    const p = { nComponents: 2, nNeighbors: 15, minDist: 0.1, nEpochs: "default", random: "mulberry32(42)" };
    return { params: p, run: () => new UMAP({ nComponents: 2, random: mulberry32(42) }).fit(X) };
  }
  const TSNE = (await import(require.resolve("tsne-js"))).default;
  const p = { dim: 2, perplexity: 30, earlyExaggeration: 4, learningRate: 100, nIter: 1000, metric: "euclidean" };
  return {
    params: p,
    run: () => {
      const m = new TSNE(p);
      m.init({ data: X, type: "dense" });
      m.run();
      return m.getOutput();
    },
  };
}

const a = args(process.argv.slice(2));
if (a.one) {
  // Child: one library call, its time and output on stdout.
  const [peer, method, n, dims] = [a.peer, a.one, Number(a.n), Number(a.dims)];
  const X = load(a["data-dir"], n, dims);
  const job = await runOne(peer, method, X);
  const t0 = performance.now();
  const Y = job.run();
  const ms = performance.now() - t0;
  const coords = new Array(2 * n);
  for (let i = 0; i < n; ++i) (coords[2 * i] = Number(Y[i][0])), (coords[2 * i + 1] = Number(Y[i][1]));
  const pkg = peer;
  process.stdout.write(
    JSON.stringify({ peer, version: version(pkg), method, n, dims, ms: Math.round(ms * 10) / 10, params: job.params, coords }) + "\n",
  );
} else {
  const dir = a["data-dir"];
  if (!dir) throw new Error("--data-dir is required");
  const sizes = (a.sizes || "1000,5000").split(",").map(Number);
  const dims = Number(a.dims || 50);
  const budget = Number(a["budget-s"] || 120);
  for (const n of sizes)
    for (const { peer, method } of RUNS) {
      if (peer === "@saehrimnir/druidjs" && method === "mds" && n > 5000) {
        console.log(JSON.stringify({ peer, method, n, dims, skipped: "O(N²) memory: the full distance matrix" }));
        continue;
      }
      const t0 = Date.now();
      const r = spawnSync(
        process.execPath,
        ["--max-old-space-size=8192", fileURLToPath(import.meta.url), "--one", method, "--peer", peer, "--n", String(n), "--dims", String(dims), "--data-dir", dir],
        { timeout: budget * 1000, maxBuffer: 1 << 30, encoding: "utf8" },
      );
      const line = (r.stdout || "").trim().split("\n").pop();
      if (r.error || r.status !== 0 || !line) {
        const why = r.error && r.error.code === "ETIMEDOUT" ? `exceeded the budget of ${budget} s` : `failed: ${errorLine(r.stderr || String(r.error))}`;
        console.log(JSON.stringify({ peer, version: version(peer), method, n, dims, skipped: why }));
        console.error(`${peer} ${method} ${n}: ${why}`);
        continue;
      }
      console.log(line);
      console.error(`${peer} ${method} ${n}: ${JSON.parse(line).ms} ms (wall ${Date.now() - t0} ms)`);
    }
}
