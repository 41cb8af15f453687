#!/usr/bin/env bash
# A day-long random world (bench/sweep, seed 5 drawn for 24 h): a restart at hour 17 matched a
# stop's level from 13 h before only because the bias walk's sigma had grown that wide, and the
# heading was "mended" by +1015 deg as if the bias had never moved since (auto's max 1125 deg
# where the paper's C has 277). core/bias_history now refuses that return. Fails if auto's max
# excess over the floor on this world is not below C's again, or the run lists it as a loss.
# Usage: day_long_return.sh SWEEP
set -uo pipefail
sweep="$1"
fail() { echo "FAIL: $*" >&2; exit 1; }
out="$("$sweep" 1 24 5)" || fail "sweep exited with $?"
row="$(grep -E '^ +5 +[0-9]+ ' <<<"$out")" || fail "no row for seed 5 in: $out"
auto="$(awk '{ print $6 }' <<<"$row")"
c="$(awk '{ print $10 }' <<<"$row")"
echo "day-long world 5: auto max $auto deg, C $c deg"
awk -v a="$auto" -v c="$c" 'BEGIN { exit !(a + 0 > 0 && a + 0 < c + 0) }' || fail "auto's max $auto is not below C's $c"
grep -q '^auto worse than C on 0 of 1 seeds' <<<"$out" || fail "the run lists a loss to C: $(grep '^auto worse' <<<"$out")"
