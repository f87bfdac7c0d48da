#!/bin/bash
# The study of docs/decisions/user-modelbase.md §9 (stop 68): density-matched modelbase entries
# on the density ladder's development tiles. Run from the source tree's root, tools built:
#   bench/usermb/study.sh DIR
# DIR (scratch): out/ and results/ of the ladder, ent/ ent2/ (the entries' renders), mb/ mb2/ (the
# modelbases), res-study/ (the scores), table*.md (the tables of §9). Development seeds only
# (tiles 101-109, entry renders 1001-1006). ~10 min on 2 cores (measured: 10 min under nice, load ~3).
set -euo pipefail
D=$(realpath -m "$1")
R=$D/res-study
mkdir -p "$D"
N="nice -n 10"
# 1. the ladder's rungs 50, 100, 200 (light and medium cover, seeds 101-109), canopy's defaults,
#    the thesis modelbase (out/modelbase), no ablations
$N make -f Makefile.experiments density -j2 PROGRESS=0 OUT="$D/out" RES="$D/results" \
  DENSITY_SEEDS="101 102 103 104 105 106 107 108 109" DENSITY_COVERS="light medium" DENSITY_LEVELS="50 100 200" \
  DENSITY_CLASSIFY_ABLATIONS= DENSITY_VERIFY_ABLATION= DENSITY_DETECT_ABLATIONS= DENSITY_SENSOR=
# 2. the entries: each model alone, seeds 1001-1003 at every level (1004-1006 at 100 and 200: the replication)
entries() { # ENT LEVEL:SPACING_MM SEEDS
  local lv=${2%%:*} mm=${2##*:} ini=
  [ "$lv" -le 50 ] && ini=share/params/detect-ladder.ini
  for m in earthmover obj1 sedan semi tank; do for s in $3; do
    $N python3 bench/usermb/entries.py "$1/d$lv" "$lv" "$mm" "$m" "$s" $ini
  done; done
}
for L in 50:298 100:211 200:149; do entries "$D/ent" $L "1001 1002 1003"; done
for L in 100:211 200:149; do entries "$D/ent2" $L "1004 1005 1006"; done
for L in 50 100 200; do python3 bench/usermb/modelbases.py "$D/ent/d$L" "$D/out/modelbase" "$D/mb/d$L"; done
for L in 100 200; do python3 bench/usermb/modelbases.py "$D/ent2/d$L" "$D/out/modelbase" "$D/mb2/d$L"; done
# 3. gmatch, verify, collect, score again on the rungs' candidates with each modelbase
again() { $N python3 bench/usermb/rematch.py "$@"; }
for L in 50 100 200; do
  again "$D/out/density/d$L" dense "$D/out/modelbase" "$R/d$L"
  for V in matched mixed; do again "$D/out/density/d$L" $V "$D/mb/d$L/$V" "$R/d$L"; done
  MERGE_MB=$D/mb/d$L/matched again "$D/out/density/d$L" seeds "$D/mb/d$L/seeds" "$R/d$L"
  for V in mixseeds union unionown; do MERGE_MB=$D/out/modelbase again "$D/out/density/d$L" $V "$D/mb/d$L/$V" "$R/d$L"; done
done
# the rung at 50 with the model level from 20 points/m² (collect --plan --model-density 20)
for V in dense:out/modelbase matched:mb/d50/matched mixed:mb/d50/mixed; do
  again "$D/out/density/d50" "${V%%:*}-md20" "$D/${V#*:}" "$R/d50" 20
done
for V in mixseeds union unionown; do
  MERGE_MB=$D/out/modelbase again "$D/out/density/d50" $V-md20 "$D/mb/d50/$V" "$R/d50" 20
done
for L in 100 200; do
  MERGE_MB=$D/mb2/d$L/matched again "$D/out/density/d$L" seedsB "$D/mb2/d$L/seeds" "$R/d$L"
  MERGE_MB=$D/out/modelbase again "$D/out/density/d$L" unionownB "$D/mb2/d$L/unionown" "$R/d$L"
  again "$D/out/density/d$L" mixedB "$D/mb2/d$L/mixed" "$R/d$L"
done
# the rungs at 100 and 200 with the model level from 20 too (the dense modelbase: §9 point 4)
for L in 100 200; do again "$D/out/density/d$L" dense-md20 "$D/out/modelbase" "$R/d$L" 20; done
# 4. the tables
for c in all light medium; do python3 bench/usermb/report.py "$R" $c > "$D/table-$c.md"; done
cat "$D/table-all.md"
