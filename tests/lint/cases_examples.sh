#!/bin/sh
# Runs the worked examples of docs/cases.md through `rayproof classify --method exact` and fails
# when an answer differs from the one the page prints.
#
# An example is a line inside a fenced code block of the page of the form
#     CASE LINE  ->  CLASS T T2            # optional comment
# (a tritri case's answer is its class alone).
# All examples go through one run, in page order, on standard input. The run's exit status must be
# 1 when an example expects `error - -` (an input error) and 0 otherwise; every kind must have at
# least one example, so that an edit that drops a block or changes the arrow is caught.
#
# usage: cases_examples.sh RAYPROOF DOCS_CASES_MD
set -u
bin=$1
doc=$2
[ -x "$bin" ] || { echo "not an executable: $bin"; exit 2; }
[ -f "$doc" ] || { echo "no such page: $doc"; exit 2; }
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT

awk '/^```/ { fence = !fence; next } fence && / -> / { print }' "$doc" >"$tmp/examples"
sed -E 's/[[:space:]]*->.*$//' "$tmp/examples" >"$tmp/input"
sed -E -e 's/^.*->[[:space:]]*//' -e 's/[[:space:]]*#.*$//' -e 's/[[:space:]]+/ /g' "$tmp/examples" >"$tmp/expected"
n=$(wc -l <"$tmp/input")
if [ "$n" -eq 0 ]; then
  echo "$doc: no examples (lines 'CASE -> CLASS T T2' in fenced blocks)"
  exit 1
fi
failed=0
for kind in plane sphere ellipsoid triangle box disk tritri; do
  if ! grep -qE "^[[:space:]]*$kind[[:space:]]" "$tmp/input"; then
    echo "$doc: no example for the kind '$kind'"
    failed=1
  fi
done

"$bin" classify --method exact - <"$tmp/input" >"$tmp/got" 2>"$tmp/err"
rc=$?
if grep -qx 'error - -' "$tmp/expected"; then want_rc=1; else want_rc=0; fi
if [ "$rc" -ne "$want_rc" ]; then
  echo "rayproof classify exited with $rc, expected $want_rc; its stderr:"
  cat "$tmp/err"
  failed=1
fi
got_n=$(wc -l <"$tmp/got")
if [ "$got_n" -ne "$n" ]; then
  echo "$n examples but $got_n output lines"
  failed=1
fi
i=0
while [ "$i" -lt "$n" ]; do
  i=$((i + 1))
  want=$(sed -n "${i}p" "$tmp/expected")
  got=$(sed -n "${i}p" "$tmp/got")
  if [ "$want" != "$got" ]; then
    echo "example $i: $(sed -n "${i}p" "$tmp/input")"
    echo "  the page says: $want"
    echo "  rayproof says: $got"
    failed=1
  fi
done
if [ "$failed" -ne 0 ]; then exit 1; fi
echo "$n examples of $doc: rayproof classify --method exact prints what the page says"
