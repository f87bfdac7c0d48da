#!/usr/bin/env bash
# Issue 28's time target: a 1 ha national-survey tile rendered in <= 60 s on 2 cores.
#   bench/sensor/hectare/run.sh [OUT_DIR]   (BIN=build/bin, SEED=11, THREADS=2,
#                                           SCENE=bench/sensor/hectare/hectare.scene)
# Prints wall and CPU seconds (GNU time, POV-Ray's child processes included), peak memory, the
# load average before and after (the machine is shared), points and density from truth.json.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../../.." && pwd)
bin=$(cd "${BIN:-$src/build/bin}" && pwd)
out=${1:-$src/build/bench-hectare}
mkdir -p "$out"
out=$(cd "$out" && pwd)
seed=${SEED:-11}
printf 'load average before: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f '%e %U %S %M' -o "$out/time" "$bin/rangetrace" --scene "${SCENE:-$here/hectare.scene}" \
  --seed "$seed" --threads "${THREADS:-2}" -o "$out/tile.las" --truth "$out/truth.json" 2>"$out/log"
read -r wall user sys kb <"$out/time"
printf 'load average after: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
printf 'wall %s s, CPU %s s (user %s + sys %s), peak %s MB\n' "$wall" "$(echo "$user + $sys" | bc -l)" \
  "$user" "$sys" "$(( kb / 1024 ))"
python3 - "$out/truth.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
d = t['density']
print('returns/m2 %.2f, first returns/m2 %.2f, pulses/m2 %.2f, pulses by returns %s' % (
    d['returns_per_m2'], d['first_returns_per_m2'], d['pulses_per_m2'], d['pulses_by_returns']))
PY
