#!/usr/bin/env bash
# classify's variants on already rendered simulated candidates (docs/decisions/classify.md §27):
# per variant, bench/detect/classlevel.sh (classify-sim.ini + the variant's options, collect,
# score) on a mirror of each run's candidates, so that nothing is written under the runs; then
# found / false alarms / class right per cover, and every candidate whose answer differs from the
# first variant's.
#   bench/classify/simvariants.sh BIN OUT MODELBASE RUN...   (RUN = WORK/d<level>-<cover>-<seed>)
#   VARIANTS="name:classify args (commas for spaces)" ... (default: before, --bridge 1m, + --bridge-fill,
#   + --bridge-min-share 0.1, both); SRC_TAG: the runs' candidates RUN/cands-SRC_TAG (default base).
# Development seeds only (never the experiment's).
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 BIN OUT MODELBASE RUN..." >&2; exit 2; }
bin=$1 out=$2 mb=$3
shift 3
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
variants=${VARIANTS:-"before: bridge:--bridge,1m fill:--bridge,1m,--bridge-fill,true share:--bridge,1m,--bridge-min-share,0.1 both:--bridge,1m,--bridge-fill,true,--bridge-min-share,0.1"}
names=()
for v in $variants; do
  name=${v%%:*}
  names+=("$name")
  args=${v#*:}
  runs=()
  for run in "$@"; do
    m=$out/runs/$(basename "$run")
    c=$m/cands-$name
    mkdir -p "$c"
    ln -sf "$run/truth.json" "$m/truth.json"
    cp "$run/cands-${SRC_TAG:-base}/index.json" "$c/"
    for p in "$run/cands-${SRC_TAG:-base}"/*.pcd; do ln -sf "$p" "$c/"; done
    runs+=("$m")
  done
  echo "== $name (${args//,/ })"
  CLASSIFY_ARGS="${args//,/ }" "$src/bench/detect/classlevel.sh" "$bin" "$out/$name" "$name" "$mb" "${runs[@]}"
  python3 - "$out/$name/score.json" <<'PY'
import json, math, sys
def wilson(k, n):
    if n == 0: return "-"
    z, p = 1.96, k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return "%d/%d = %.1f%% [%.1f, %.1f]" % (k, n, 100 * p, 100 * (c - h), 100 * (c + h))
for s in json.load(open(sys.argv[1]))["summary"]:
    if s["noise_mm"] != "all": continue
    fa = round(s["false_alarms_any_level_per_ha"] * s["area_ha"])
    print("%s: found %s, false alarms %d (%.1f/ha), class right %s" % (
        s["cover"], wilson(s["found_any_level"], s["true"]), fa, s["false_alarms_any_level_per_ha"],
        wilson(s["class_right_any_level"], s["found_any_level"])))
PY
done
python3 - "$out" "${names[@]}" -- "$@" <<'PY'
import json, os, sys
out = sys.argv[1]
k = sys.argv.index("--")
names, runs = sys.argv[2:k], [os.path.basename(r) for r in sys.argv[k + 1:]]
def answer(n, r, c):
    j = json.load(open(os.path.join(out, "runs", r, "cands-" + n, c, "class.json")))
    m = j.get("measured") or {}
    return (j["class"] or j["reason"]), "x".join("%.2f" % v for v in m.get("size") or [])
for r in runs:
    d = os.path.join(out, "runs", r, "cands-" + names[0])
    ids = sorted(p[:-4] for p in os.listdir(d) if p.endswith(".pcd"))
    for n in names[1:]:
        for c in ids:
            a, b = answer(names[0], r, c), answer(n, r, c)
            if a != b:
                print(f"{n} {r} {c}: {a[0]} {a[1]} -> {b[0]} {b[1]}")
PY
