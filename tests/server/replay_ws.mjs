// One viewer of a live replay over the real server: hello, the first frame, a seek, a bad op; prints what
// it saw as JSON. Usage: node --experimental-websocket replay_ws.mjs BASE_URL REPLAY_ID
const [base, id] = process.argv.slice(2);
// Access control is on: the admin token the test script made (tests/support/cli_checks.sh use_token).
const auth = process.env.TRAILSCOPE_TOKEN ? { Authorization: `Bearer ${process.env.TRAILSCOPE_TOKEN}` } : {};
const ws = new WebSocket(`${base.replace('http', 'ws')}/api/v1/replays/${id}/ws`, { headers: auth });
ws.binaryType = 'arraybuffer';
const out = { frames: [] };
const timer = setTimeout(() => { console.log(JSON.stringify({ error: 'timeout', ...out })); process.exit(1); }, 30000);
const finish = () => { clearTimeout(timer); console.log(JSON.stringify(out)); ws.close(); process.exit(0); };
ws.onmessage = (m) => {
  if (typeof m.data !== 'string') {
    // "TSRF", uint32 LE JSON length, JSON, then the PNGs.
    const bytes = new Uint8Array(m.data);
    const view = new DataView(m.data);
    out.magic = new TextDecoder().decode(bytes.slice(0, 4));
    const len = view.getUint32(4, true);
    const head = JSON.parse(new TextDecoder().decode(bytes.slice(8, 8 + len)));
    const png = bytes.slice(8 + len + head.depth_png[0], 8 + len + head.depth_png[0] + 4);
    out.png = String.fromCharCode(...png.slice(1, 4));
    out.frames.push(head.index);
    if (head.index === 0 && out.frames.length === 1) ws.send(JSON.stringify({ op: 'seek', frame: 5 }));
    if (head.index === 5) { out.seeked = 5; ws.send(JSON.stringify({ op: 'fly' })); }
    return;
  }
  const msg = JSON.parse(m.data);
  if (!out.first) out.first = msg.type;
  if (msg.type === 'error') { out.error_param = msg.param; finish(); }
};
