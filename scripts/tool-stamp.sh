#!/usr/bin/env bash
# tool-stamp.sh BINARY STAMP: writes the sha256 of BINARY to STAMP only when it differs from
# the one recorded there, so STAMP's time changes only with the binary's content. The
# experiment's artifacts depend on STAMP, not on BINARY (Makefile.experiments).
set -euo pipefail
bin=$1 stamp=$2
[ -f "$bin" ] || exit 0   # a dry run before the first build: nothing to hash yet
h=$(sha256sum <"$bin" | cut -d' ' -f1)
[ "$h" = "$(cat "$stamp" 2>/dev/null)" ] && exit 0
mkdir -p "$(dirname "$stamp")"
echo "$h" >"$stamp.tmp" && mv -f "$stamp.tmp" "$stamp"
echo "new   $bin (sha256 ${h:0:12})"
