// Uploads a file over HTTP while listening on the WebSocket, and prints what the job events showed.
// Usage: node --experimental-websocket ws_events.mjs BASE_URL FILE NAME
import { readFileSync } from 'node:fs';

const [base, file, name] = process.argv.slice(2);
// Access control is on: the admin token the test script made (tests/support/cli_checks.sh use_token).
const auth = process.env.TRAILSCOPE_TOKEN ? { Authorization: `Bearer ${process.env.TRAILSCOPE_TOKEN}` } : {};
const ws = new WebSocket(base.replace('http', 'ws') + '/api/v1/ws', { headers: auth });
const events = [];
const timer = setTimeout(() => { console.log(JSON.stringify({ error: 'timeout', events })); process.exit(1); }, 60000);
await new Promise((resolve, reject) => {
  ws.onmessage = (m) => { if (JSON.parse(m.data).type === 'hello') resolve(); };
  ws.onerror = reject;
});
ws.onmessage = (m) => {
  const msg = JSON.parse(m.data);
  if (msg.type !== 'job' || msg.job.dataset !== name) return;
  events.push(msg.job);
  if (['done', 'failed', 'cancelled'].includes(msg.job.state)) {
    clearTimeout(timer);
    const progress = events.map((e) => e.progress);
    console.log(JSON.stringify({
      first: events[0].state,
      last: msg.job.state,
      running: events.some((e) => e.state === 'running'),
      monotonic: progress.every((p, i) => i === 0 || p >= progress[i - 1]),
      count: events.length,
      flights: msg.job.result ? msg.job.result.flights : null,
    }));
    ws.close();
    process.exit(0);
  }
};
const res = await fetch(`${base}/api/v1/datasets?name=${name}`, { method: 'POST', body: readFileSync(file), headers: auth });
if (res.status !== 202) { console.log(JSON.stringify({ error: `status ${res.status}` })); process.exit(1); }
