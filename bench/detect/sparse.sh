#!/usr/bin/env bash
# detect on a few points spread wide (issue 25 item 6): wall time, peak memory and exit status
# of the two round3 reproducers (refused: more DTM cells than 4e6 + 16 per point) and of tiles
# within that bound, where only the DTM holes near points are relaxed.
#   bench/detect/sparse.sh [build dir] [detect binary to compare, e.g. an older build's]
set -uo pipefail
build=${1:-build}
bins=("$build/bin/detect")
[ -n "${2:-}" ] && bins+=("$2")
here=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# pcd NAME "x y z;x y z;...": a float64 PCD.
pcd() {
  python3 - "$tmp/$1.pcd" "$2" <<'PY'
import struct, sys
pts = [tuple(map(float, p.split())) for p in sys.argv[2].split(';')]
n = len(pts)
h = ("VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\n"
     f"WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA binary\n")
open(sys.argv[1], 'wb').write(h.encode() + b''.join(struct.pack('<ddd', *p) for p in pts))
PY
}
pcd sparse900 "0 0 0;900 900 3;761 619 1.4;115 186 3.3;450 870 3.4;126 66 1.5;794 365 0.7;143 662 3;7 491 1.6;681 800 2.4"
data=$here/tests/detect/data
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-44s %-8s %8s %10s  %s\n' case binary "wall s" "peak MB" exit
for bin in "${bins[@]}"; do
  for c in "$data/detect-2200m-10pts.pcd|" "$data/detect-line-9000km-10pts.pcd|" \
           "$tmp/sparse900.pcd|" "$data/detect-2200m-10pts.pcd|--cell 2"; do
    f=${c%%|*} extra=${c#*|}
    rm -rf "$tmp/out"
    # shellcheck disable=SC2086
    timeout 900 /usr/bin/time -f '%e %M' -o "$tmp/t.txt" "$bin" -q $extra -i "$f" -o "$tmp/out" 2>/dev/null
    rc=$?
    read -r secs kib < <(tail -n 1 "$tmp/t.txt")
    printf '%-44s %-8s %8s %10d  %s\n' "$(basename "$f") $extra" "$( [ "$bin" = "${bins[0]}" ] && echo this || echo other)" \
      "$secs" "$((kib / 1024))" "$rc"
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
