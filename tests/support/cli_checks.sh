# Checks for the CLI end-to-end scripts (sourced): counts passes and failures in PASS and FAIL, prints one
# line a check; the script ends with `finish`, which prints "N passed, M failed" and fails on any failure.
PASS=0 FAIL=0

check() {  # check NAME EXPECTED ACTUAL
  if [ "$2" == "$3" ]; then PASS=$((PASS + 1)); echo "ok   $1"
  else FAIL=$((FAIL + 1)); echo "FAIL $1: expected '$2', got '$3'"; fi
}
contains() {  # contains NAME NEEDLE FILE
  if grep -qF -- "$2" "$3"; then PASS=$((PASS + 1)); echo "ok   $1"
  else FAIL=$((FAIL + 1)); echo "FAIL $1: '$2' not in: $(head -c 400 "$3")"; fi
}
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }  # json EXPR < FILE

finish() {
  echo "$PASS passed, $FAIL failed"
  [ "$FAIL" -eq 0 ]
}

# Access control is on in every server: `use_token DATA_DIR` creates an admin token in a data folder (before
# `serve` starts over it) with `$BIN token create` and exports it as TRAILSCOPE_TOKEN; then every `curl` of the
# script sends it (the function below), and so do the node helpers (they read TRAILSCOPE_TOKEN).
use_token() {
  TRAILSCOPE_TOKEN=$("$BIN" token create --data-dir "$1" --name test-admin --role admin --json | json 'd["token"]')
  export TRAILSCOPE_TOKEN
}
curl() {
  if [ -n "${TRAILSCOPE_TOKEN:-}" ]; then command curl -H "Authorization: Bearer $TRAILSCOPE_TOKEN" "$@"
  else command curl "$@"; fi
}

# `start_server DATA_DIR [serve flags...]`: `$BIN serve` over DATA_DIR on a free loopback port, its output in
# $TMP/server.log; sets SERVER_PID, PORT and URL once the server says where it listens. The server reads every
# stored dataset before it listens, slow on a loaded CI machine running other tests beside this one: the wait
# is START_SERVER_SECONDS (default 90 s). A server that does not
# come up counts as a failed check, with its log, rather than leaving every later check to fail on an empty URL.
# `stop_server` ends it with SIGTERM and waits for it. The script's EXIT trap kills SERVER_PID if it is left.
start_server() {
  # Emptied here, not by the child's `>`: the child truncates only once it runs, and a restart's first look
  # at the log could otherwise read the previous server's port.
  : > "$TMP/server.log"
  "$BIN" serve --data-dir "$1" --port 0 --host 127.0.0.1 --web-root /nonexistent "${@:2}" >> "$TMP/server.log" 2>&1 &
  SERVER_PID=$!
  PORT=
  local started=$SECONDS
  while [ $((SECONDS - started)) -lt "${START_SERVER_SECONDS:-90}" ] && kill -0 "$SERVER_PID" 2>/dev/null; do
    PORT=$(grep -oE '127\.0\.0\.1:[0-9]+' "$TMP/server.log" | head -1 | cut -d: -f2)
    [ -n "$PORT" ] && break
    sleep 0.1
  done
  URL="http://127.0.0.1:$PORT"
  if [ -z "$PORT" ]; then
    FAIL=$((FAIL + 1))
    echo "FAIL server started: no listening line after $((SECONDS - started)) s; its log:"
    tail -20 "$TMP/server.log"
  fi
}
stop_server() { kill -TERM "$SERVER_PID"; wait "$SERVER_PID" 2>/dev/null; SERVER_PID=; }
