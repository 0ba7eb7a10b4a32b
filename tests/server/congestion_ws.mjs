// Submits a congestion request over HTTP while listening on the WebSocket, and prints what the job's events
// showed: the first and last states, whether progress never went back, the stages, and the summary.
// Usage: node --experimental-websocket congestion_ws.mjs BASE_URL BODY_JSON
const [base, body] = process.argv.slice(2);
// Access control is on: the admin token the test script made (tests/support/cli_checks.sh use_token).
const auth = process.env.TRAILSCOPE_TOKEN ? { Authorization: `Bearer ${process.env.TRAILSCOPE_TOKEN}` } : {};
const ws = new WebSocket(base.replace('http', 'ws') + '/api/v1/ws', { headers: auth });
const events = [];
let job = null;
const timer = setTimeout(() => { console.log(JSON.stringify({ error: 'timeout', events })); process.exit(1); }, 120000);
await new Promise((resolve, reject) => {
  ws.onmessage = (m) => { if (JSON.parse(m.data).type === 'hello') resolve(); };
  ws.onerror = reject;
});
const finish = () => {
  clearTimeout(timer);
  const mine = events.filter((e) => e.id === job);
  const progress = mine.map((e) => e.progress);
  const last = mine[mine.length - 1];
  console.log(JSON.stringify({
    job,
    first: mine[0].state,
    last: last.state,
    running: mine.some((e) => e.state === 'running'),
    monotonic: progress.every((p, i) => i === 0 || p >= progress[i - 1]),
    partial: mine.some((e) => e.state === 'running' && e.progress > 0 && e.progress < 1),
    stages: [...new Set(mine.map((e) => e.stage).filter((s) => s))],
    kind: last.kind,
    result: last.result,
  }));
  ws.close();
  process.exit(0);
};
ws.onmessage = (m) => {
  const msg = JSON.parse(m.data);
  if (msg.type !== 'job' || msg.job.kind !== 'congestion') return;
  events.push(msg.job);
  if (job && msg.job.id === job && ['done', 'failed', 'cancelled'].includes(msg.job.state)) finish();
};
const res = await fetch(`${base}/api/v1/congestion`, { method: 'POST', body, headers: { 'Content-Type': 'application/json', ...auth } });
if (res.status !== 202) { console.log(JSON.stringify({ error: `status ${res.status}`, body: await res.text() })); process.exit(1); }
job = (await res.json()).job.id;
// The job may have ended before the answer of the POST arrived.
if (events.some((e) => e.id === job && ['done', 'failed', 'cancelled'].includes(e.state))) finish();
