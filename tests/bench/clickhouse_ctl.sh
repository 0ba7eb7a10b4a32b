#!/usr/bin/env bash
# Starts and stops a private ClickHouse server (Debian's clickhouse-server 18.16) on 127.0.0.1 only, with
# its own data folder, for the peer benchmark. No systemd and no init script: the server runs in the
# background and is stopped by its PID. Debian's package does not start it at install, and its stock
# config.xml sets no listen_host (both lines sit inside a comment), so this copy adds 127.0.0.1 explicitly.
#
#   clickhouse_ctl.sh start DIR [HTTP_PORT]   # prints nothing; waits until /ping answers (≤ 30 s)
#   clickhouse_ctl.sh stop DIR                # TERM, then KILL after 10 s; removes nothing
#
# Ports: HTTP_PORT (default 18123), native HTTP_PORT+1, interserver HTTP_PORT+2; none of the defaults
# (8123/9000/9009), so a ClickHouse someone else runs on this machine is left alone.
set -euo pipefail

cmd=${1:?usage: clickhouse_ctl.sh start|stop DIR [HTTP_PORT]}
dir=${2:?usage: clickhouse_ctl.sh start|stop DIR [HTTP_PORT]}
port=${3:-18123}

case "$cmd" in
start)
  command -v clickhouse-server >/dev/null || { echo "clickhouse-server is not installed (make deps-bench)" >&2; exit 1; }
  mkdir -p "$dir/data" "$dir/log" "$dir/tmp" "$dir/user_files" "$dir/format_schemas"
  dir=$(cd "$dir" && pwd)
  cp /etc/clickhouse-server/config.xml /etc/clickhouse-server/users.xml "$dir/"
  # Paths into DIR, private ports, no HTTPS/secure ports (no certificate needed), loopback only.
  sed -i \
    -e "s#/var/lib/clickhouse/tmp/#$dir/tmp/#g" \
    -e "s#/var/lib/clickhouse/user_files/#$dir/user_files/#g" \
    -e "s#/var/lib/clickhouse/format_schemas/#$dir/format_schemas/#g" \
    -e "s#/var/lib/clickhouse/#$dir/data/#g" \
    -e "s#/var/log/clickhouse-server/#$dir/log/#g" \
    -e "s#<http_port>8123</http_port>#<http_port>$port</http_port>#" \
    -e "s#<tcp_port>9000</tcp_port>#<tcp_port>$((port + 1))</tcp_port>#" \
    -e "s#<interserver_http_port>9009</interserver_http_port>#<interserver_http_port>$((port + 2))</interserver_http_port>#" \
    -e "s#<yandex>#<yandex>\n    <listen_host>127.0.0.1</listen_host>#" \
    "$dir/config.xml"
  # users.xml's default profile: keep stock settings (max_threads = cores, as ClickHouse picks).
  # The server refuses to run as root only when asked to drop privileges; run it in the foreground,
  # backgrounded by the shell, so that its PID is ours.
  (cd "$dir" && exec clickhouse-server --config-file="$dir/config.xml" >"$dir/log/stdout.txt" 2>&1) &
  echo $! >"$dir/clickhouse.pid"
  for _ in $(seq 1 300); do
    if curl -fsS "http://127.0.0.1:$port/ping" >/dev/null 2>&1; then exit 0; fi
    if ! kill -0 "$(cat "$dir/clickhouse.pid")" 2>/dev/null; then
      echo "clickhouse-server exited during start; last log lines:" >&2
      tail -n 20 "$dir/log/stdout.txt" "$dir/log/clickhouse-server.err.log" 2>/dev/null >&2 || true
      exit 1
    fi
    sleep 0.1
  done
  echo "clickhouse-server did not answer on 127.0.0.1:$port within 30 s" >&2
  exit 1
  ;;
stop)
  [ -f "$dir/clickhouse.pid" ] || exit 0
  pid=$(cat "$dir/clickhouse.pid")
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 1 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid" 2>/dev/null || true; fi
  fi
  rm -f "$dir/clickhouse.pid"
  ;;
*)
  echo "usage: clickhouse_ctl.sh start|stop DIR [HTTP_PORT]" >&2
  exit 2
  ;;
esac
