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
