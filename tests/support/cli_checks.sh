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
