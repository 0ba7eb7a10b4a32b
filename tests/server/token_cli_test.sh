#!/usr/bin/env bash
# `trailscope token create|list|revoke` end to end, and access control over a real server: the first admin
# token and the sign-in URL `serve` prints, 401/403 by role, a token created and one revoked by the CLI while
# the server runs, the session cookie of the one-time code (which works once), --public-reads.
# Usage: token_cli_test.sh TRAILSCOPE_BIN
set -uo pipefail
BIN=$(readlink -f "$1")
TMP=$(mktemp -d)
SERVER_PID=
cleanup() { [ -n "$SERVER_PID" ] && kill -9 "$SERVER_PID" 2>/dev/null; rm -rf "$TMP"; }
trap cleanup EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../support/cli_checks.sh"
D="$TMP/data"

# --- the CLI -------------------------------------------------------------------------------------------
"$BIN" token create --data-dir "$D" --name alice --role writer --json > "$TMP/alice.json"
check "create exit 0" 0 $?
ALICE=$(json 'd["token"]' < "$TMP/alice.json")
ALICE_ID=$(json 'd["id"]' < "$TMP/alice.json")
check "create json fields" "alice writer" "$(json 'd["name"] + " " + d["role"]' < "$TMP/alice.json")"
check "token form" yes "$([[ "$ALICE" =~ ^tsk_${ALICE_ID}_[0-9a-f]{64}$ ]] && echo yes || echo no)"
"$BIN" token create --data-dir "$D" --name bob --role reader > "$TMP/bob.txt"
check "create text exit 0" 0 $?
BOB=$(tail -1 "$TMP/bob.txt")
contains "create text says once" "shown once" "$TMP/bob.txt"
check "text token form" yes "$([[ "$BOB" =~ ^tsk_[0-9a-f]{12}_[0-9a-f]{64}$ ]] && echo yes || echo no)"
BOB_ID=$(echo "$BOB" | cut -d_ -f2)

"$BIN" token list --data-dir "$D" --json > "$TMP/list.json"
check "list json" "alice:writer,bob:reader" \
  "$(json '",".join(t["name"] + ":" + t["role"] for t in d)' < "$TMP/list.json")"
check "list json fields" "created,id,name,role" "$(json '",".join(sorted(d[0]))' < "$TMP/list.json")"
"$BIN" token list --data-dir "$D" > "$TMP/list.txt"
contains "list text names bob" "$BOB_ID" "$TMP/list.txt"
# No secret anywhere: not in the lists, not in the data folder.
check "no secret in lists" 0 "$(cat "$TMP/list.json" "$TMP/list.txt" | grep -c -e "${ALICE#tsk_*_}" -e "${BOB#tsk_*_}")"
check "no secret on disk" 0 "$(grep -rc -e "${ALICE#tsk_*_}" -e "${BOB#tsk_*_}" "$D" | awk -F: '{s += $2} END {print s}')"
check "tokens.json is private" 600 "$(stat -c %a "$D/tokens.json")"

# Errors: a message and a non-zero exit.
"$BIN" token create --data-dir "$D" --name carol --role root 2> "$TMP/err"
check "bad role exit 2" 2 $?
check "bad role message" "trailscope: role must be reader, writer or admin" "$(cat "$TMP/err")"
"$BIN" token create --data-dir "$D" --name 'car ol' --role reader 2> "$TMP/err"
check "bad name exit 2" 2 $?
contains "bad name message" "name: must be 1-64 of" "$TMP/err"
"$BIN" token create --data-dir "$D" --role reader 2> "$TMP/err"
check "missing name exit" 106 $?
"$BIN" token revoke --data-dir "$D" 0123456789ab 2> "$TMP/err"
check "revoke unknown exit 2" 2 $?
check "revoke unknown message" "trailscope: no token '0123456789ab' in $D/tokens.json" "$(cat "$TMP/err")"
"$BIN" token 2> "$TMP/err"
check "token without a verb fails" 106 $?
for verb in create list revoke; do
  "$BIN" token "$verb" --help > "$TMP/help.txt"
  check "$verb --help exit 0" 0 $?
  contains "$verb --help names --data-dir" "--data-dir" "$TMP/help.txt"
done
"$BIN" token create --help > "$TMP/help.txt"
contains "create --help names --role" "reader | writer | admin" "$TMP/help.txt"

# --- a real server ---------------------------------------------------------------------------------------
code() { command curl -s -o "$TMP/body.json" -w '%{http_code}' "$@"; }  # code CURL_ARGS: the status
as() { local t=$1; shift; code -H "Authorization: Bearer $t" "$@"; }   # as TOKEN CURL_ARGS

# A data folder with no token: serve makes the first admin's and prints it once, with the sign-in URL.
start_server "$TMP/fresh"
contains "first admin token printed" "first admin token (shown once, store it): tsk_" "$TMP/server.log"
ADMIN=$(grep -oE 'tsk_[0-9a-f]{12}_[0-9a-f]{64}' "$TMP/server.log" | head -1)
LOGIN=$(grep -oE "http://127\.0\.0\.1:$PORT/\?login=[0-9a-f]{64}" "$TMP/server.log" | head -1)
check "sign-in URL printed" yes "$([ -n "$LOGIN" ] && echo yes || echo no)"
check "first token listed" "admin:admin" \
  "$("$BIN" token list --data-dir "$TMP/fresh" --json | json '",".join(t["name"] + ":" + t["role"] for t in d)')"
check "health anonymous" 200 "$(code "$URL/api/v1/health")"
check "list anonymous" 401 "$(code "$URL/api/v1/datasets")"
check "401 body" "unauthorized authorization" "$(json 'd["error"] + " " + d["param"]' < "$TMP/body.json")"
check "delete anonymous before lookup" 401 "$(code -X DELETE "$URL/api/v1/datasets/nope")"
check "delete as admin" 404 "$(as "$ADMIN" -X DELETE "$URL/api/v1/datasets/nope")"
# The one-time code: a session cookie, once.
code="${LOGIN##*login=}"
check "sign in with the code" 200 \
  "$(code -c "$TMP/jar" -H 'Content-Type: application/json' -d "{\"login\":\"$code\"}" "$URL/api/v1/session")"
check "signed in as" "local admin" "$(json 'd["owner"] + " " + d["role"]' < "$TMP/body.json")"
check "cookie is HttpOnly" 1 "$(grep -c '^#HttpOnly_127.0.0.1.*trailscope_session' "$TMP/jar")"
check "cookie works" 200 "$(code -b "$TMP/jar" "$URL/api/v1/tokens")"
check "code works once" 401 \
  "$(code -H 'Content-Type: application/json' -d "{\"login\":\"$code\"}" "$URL/api/v1/session")"
check "sign out" 204 "$(code -b "$TMP/jar" -X DELETE "$URL/api/v1/session")"
check "cookie ended" 401 "$(code -b "$TMP/jar" "$URL/api/v1/tokens")"
stop_server
# Restarted over a folder with tokens: no new first token.
start_server "$TMP/fresh"
check "no second first token" 0 "$(grep -c 'first admin token' "$TMP/server.log")"
stop_server

# Roles, and the CLI changing tokens under a running server.
start_server "$D"
check "reader reads" 200 "$(as "$BOB" "$URL/api/v1/datasets")"
check "reader may not delete" 403 "$(as "$BOB" -X DELETE "$URL/api/v1/datasets/nope")"
check "403 detail" "this needs the writer role; token $BOB_ID ('bob') has the reader role" \
  "$(json 'd["detail"]' < "$TMP/body.json")"
check "writer deletes (none here)" 404 "$(as "$ALICE" -X DELETE "$URL/api/v1/datasets/nope")"
check "writer may not list tokens" 403 "$(as "$ALICE" "$URL/api/v1/tokens")"
DAVE=$("$BIN" token create --data-dir "$D" --name dave --role admin --json | json 'd["token"]')
check "token created by the CLI works at once" 200 "$(as "$DAVE" "$URL/api/v1/tokens")"
"$BIN" token revoke --data-dir "$D" "$ALICE_ID" > "$TMP/out.txt"
check "revoke exit 0" 0 $?
check "revoke message" "revoked token $ALICE_ID" "$(cat "$TMP/out.txt")"
sleep 1.1  # the server stats tokens.json at most once a second
check "token revoked by the CLI refused" 401 "$(as "$ALICE" -X DELETE "$URL/api/v1/datasets/nope")"
check "wrong scheme" 401 "$(code -H "Authorization: Basic YTpi" "$URL/api/v1/datasets")"
stop_server
start_server "$D" --public-reads
check "public reads" 200 "$(code "$URL/api/v1/datasets")"
check "public reads: no anonymous delete" 401 "$(code -X DELETE "$URL/api/v1/datasets/nope")"
check "public reads: tokens stay an admin's" 401 "$(code "$URL/api/v1/tokens")"
stop_server

finish
