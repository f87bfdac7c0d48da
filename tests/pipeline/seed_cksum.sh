#!/usr/bin/env bash
# scripts/cksum.sh, the experiment's seeds (Makefile.experiments `seed`) and the scene recipes'
# vehicle counts and clutter kinds (mk/scenes.mk): the CRC of POSIX cksum computed in bash alone
# must be the number `printf '%s' KEY | cksum` prints first, for the keys the experiment uses
# and for any bytes (empty, one byte, over 255 bytes: a length of two bytes, bytes >= 128).
set -u
src=$1
fail() { echo "FAIL: $*" >&2; exit 1; }
ck="$src/scripts/cksum.sh"
# known answers (POSIX cksum)
[ "$("$ck" '')" = 4294967295 ] || fail "the empty text gives $("$ck" ''), not 4294967295"
[ "$("$ck" a)" = 1220704766 ] || fail "'a' gives $("$ck" a), not 1220704766"
[ "$("$ck" 'tank/circle')" = "$(printf '%s' 'tank/circle' | cksum | cut -d' ' -f1)" ] || fail "tank/circle differs from cksum"
long=$(printf 'x%.0s' $(seq 300))
keys=("scenes/light/101/0" "clutter/dense/7" "vehicles/medium/3" "sedan/unoccluded/0" "$long" $'\xc3\xbcn\xc3\xaf' "a b" "it's")
for i in $(seq 15); do keys+=("$(head -c $((i * 7)) /dev/urandom | tr -d '\0\n')"); done
for k in "${keys[@]}"; do
  want=$(printf '%s' "$k" | cksum | cut -d' ' -f1)
  [ "$("$ck" "$k")" = "$want" ] || fail "cksum.sh '$k' gives $("$ck" "$k"), cksum $want"
done
# --mod N --add A: A + CRC mod N (the vehicles per tile: 3 + CRC mod 6)
for k in "vehicles/light/1" "clutter/medium/5"; do
  crc=$(printf '%s' "$k" | cksum | cut -d' ' -f1)
  [ "$("$ck" --mod 6 --add 3 "$k")" = $((3 + crc % 6)) ] || fail "--mod 6 --add 3 '$k' is not $((3 + crc % 6))"
done
# sourced, as make's $(shell) runs it (Makefile.experiments `seed`)
[ "$(cd "$src" && bash -c ". scripts/cksum.sh 'scenes/light/101/0'")" = "$(printf '%s' 'scenes/light/101/0' | cksum | cut -d' ' -f1)" ] ||
  fail "sourced, cksum.sh gives another number"
rc=0; "$ck" 2>/dev/null || rc=$?
[ $rc -eq 2 ] || fail "no text gave status $rc, not 2"
echo "ok: seed cksum"
