#!/bin/sh
# Fails when a source subscripts a conditional choice of arrays, `(c ? a : b)[k]`.
#
# GCC 12.2 (Debian 12) miscompiles that form whenever the index is instrumented by UBSan's
# integer-divide-by-zero, shift or signed-integer-overflow checks (all in -fsanitize=undefined, at
# -O0 as well as -O1): the index's saved operand is evaluated in one arm of the conditional only, and
# the other arm reads an uninitialized temporary. The sanitizer tree then computed wrong values and,
# when the stack held a negative number, stopped with "index -2 out of bounds for type 'double [3]'"
# (tests/certified_test.cpp, one run in eight with address randomization, never without it). Clang is
# not affected. Write `c ? a[k] : b[k]` instead.
#
# usage: conditional_subscript.sh SOURCE_DIR
set -u
cd "$1" || exit 2
# A parenthesised conditional with no parentheses inside, then a subscript; comments are ignored.
pat='\([^()?;]*\?[^()?:;]*:[^()?:;]*\)[[:space:]]*\['
hits=$(grep -rnE "$pat" --include='*.cpp' --include='*.h' --include='*.cc' --include='*.c' \
         include src verify tests python bench fuzz examples 2>/dev/null |
       while IFS= read -r hit; do
         code=${hit#*:*:}
         code=${code%%//*}
         printf '%s\n' "$code" | grep -qE "$pat" && printf '%s\n' "$hit"
       done)
if [ -n "$hits" ]; then
  echo "A conditional choice of arrays is subscripted; GCC 12's -fsanitize=undefined miscompiles it (see $0):"
  echo "$hits"
  exit 1
fi
echo "no subscripted conditional (c ? a : b)[k] in the sources"
