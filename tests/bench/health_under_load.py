#!/usr/bin/env python3
"""Health latency while heavy synchronous work runs: starts `trailscope serve` on an empty data folder,
sends HEAVY concurrent POST /api/v1/projections (ROWS rows, method force, ITERATIONS iterations, backend
cpu: minutes of work each) and polls GET /api/v1/health every 20 ms for SECONDS seconds, each poll with a
2 s timeout. Prints one JSON line: the health latencies' p50/p99/max in ms, the polls and timeouts, and
what the heavy requests got. Then closes the heavy connections and checks that the server's CPU use falls
(the compute pool cancels the work of a client that left).

usage: health_under_load.py BINARY [--seconds 20] [--heavy 2] [--rows 5000] [--iterations 10000]
"""
import argparse, json, os, random, re, shutil, socket, subprocess, sys, tempfile, threading, time


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("--seconds", type=float, default=20)
    ap.add_argument("--heavy", type=int, default=2)
    ap.add_argument("--rows", type=int, default=5000)
    ap.add_argument("--iterations", type=int, default=10000)
    a = ap.parse_args()
    data = tempfile.mkdtemp(prefix="health_bench_")
    server = subprocess.Popen([a.binary, "serve", "--data-dir", data, "--port", "0", "--web-root", "/nonexistent"],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        port = None
        for line in server.stdout:
            m = re.search(r"127\.0\.0\.1:(\d+)", line)
            if m:
                port = int(m.group(1))
                break
        rng = random.Random(7)
        rows = [[rng.random() for _ in range(8)] for _ in range(a.rows)]
        body = json.dumps({"table": {"rows": rows}, "method": "force", "iterations": a.iterations,
                           "backend": "cpu"}).encode()
        heavy_results, socks = [], []

        def heavy():
            s = socket.create_connection(("127.0.0.1", port))
            socks.append(s)
            s.sendall(b"POST /api/v1/projections HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
                      b"Content-Length: %d\r\nConnection: close\r\n\r\n" % (port, len(body)) + body)
            try:
                s.settimeout(a.seconds + 5)
                head = s.recv(200).decode(errors="replace").split("\r\n")[0]
                heavy_results.append(head or "closed")
            except (socket.timeout, OSError):
                heavy_results.append("no answer")

        threads = [threading.Thread(target=heavy, daemon=True) for _ in range(a.heavy)]
        for t in threads:
            t.start()
        time.sleep(1.0)  # the heavy requests are running
        lat, timeouts = [], 0
        end = time.time() + a.seconds
        while time.time() < end:
            t0 = time.perf_counter()
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
                    s.sendall(b"GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nConnection: close\r\n\r\n" % port)
                    got = b""
                    while True:
                        chunk = s.recv(65536)
                        if not chunk:
                            break
                        got += chunk
                if not got.startswith(b"HTTP/1.1 200"):
                    raise OSError("status")
                lat.append((time.perf_counter() - t0) * 1000)
            except OSError:
                timeouts += 1
            time.sleep(0.02)
        # The clients leave: the work should stop (its token set), so the server's CPU use falls.
        for s in socks:
            s.close()
        time.sleep(1.0)
        c0 = cpu_seconds(server.pid)
        time.sleep(3.0)
        cpu_after = (cpu_seconds(server.pid) - c0) / 3.0
        lat.sort()
        q = lambda p: round(lat[min(len(lat) - 1, int(p * len(lat)))], 2) if lat else None
        print(json.dumps({"bench": "health_under_load", "heavy": a.heavy, "rows": a.rows,
                          "iterations": a.iterations, "polls": len(lat) + timeouts, "timeouts": timeouts,
                          "p50_ms": q(0.5), "p99_ms": q(0.99), "max_ms": round(lat[-1], 2) if lat else None,
                          "heavy_answers": heavy_results,
                          "server_cpu_after_clients_left": round(cpu_after, 2)}))
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            print(json.dumps({"note": "server did not stop within 30 s of SIGTERM"}))
        shutil.rmtree(data, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
