#!/bin/bash
# cksum.sh [--mod N [--add A]] TEXT: POSIX cksum's CRC of TEXT's bytes (no newline added), as
# `printf '%s' TEXT | cksum` prints it first, in bash alone: the experiment's seeds and the scene
# recipes' vehicle counts and clutter kinds (Makefile.experiments `seed`, mk/scenes.mk). One
# process instead of the three of a shell pipe (bash, its subshell, cksum), each ≈ 8 ms of CPU on
# the experiment machine (docs/decisions/cost.md §18): make's $(shell) always starts a bash, which
# sources this file (`. scripts/cksum.sh KEY`) rather than starting a second bash for it. --mod N:
# the CRC modulo N, plus A.
LC_ALL=C
mod=0 add=0
while :; do
  case "${1:-}" in
    --mod) mod=$2; shift 2 ;;
    --add) add=$2; shift 2 ;;
    *) break ;;
  esac
done
[ $# -eq 1 ] || { echo "cksum.sh: usage: cksum.sh [--mod N [--add A]] TEXT" >&2; exit 2; }
text=$1
crc=0
# step BYTE: the CRC (polynomial 0x04C11DB7, most significant bit first) after one more byte.
step() {
  local k
  crc=$((crc ^ ($1 << 24)))
  for ((k = 0; k < 8; k++)); do
    if ((crc & 0x80000000)); then crc=$(((crc << 1 ^ 0x04C11DB7) & 0xFFFFFFFF)); else crc=$((crc << 1 & 0xFFFFFFFF)); fi
  done
}
for ((i = 0; i < ${#text}; i++)); do
  printf -v b '%d' "'${text:i:1}"
  step $((b & 255))
done
# then the length, least significant byte first, as many bytes as it needs
for ((n = ${#text}; n > 0; n >>= 8)); do step $((n & 255)); done
crc=$((~crc & 0xFFFFFFFF))
if [ "$mod" -gt 0 ]; then echo $((add + crc % mod)); else echo "$crc"; fi
