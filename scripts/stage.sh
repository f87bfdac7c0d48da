#!/bin/bash
# stage.sh [--launch local|slurm] [--record-failure] ARTIFACT -- COMMAND...: runs one experiment
# stage through the compiled stage runner, stagerun (tools/stagerun: its rules are in
# tools/stagerun/main.cpp and stagerun.h; docs/decisions/cost.md §19). Makefile.experiments runs
# $(BIN)/stagerun itself; this script is for a user or a script calling stage.sh by hand: it only
# finds the runner and replaces itself with it (no second copy of the rules).
# The runner: $CANOPY_BIN/stagerun, else build/bin/stagerun of this source tree.
here=${BASH_SOURCE[0]%/*}
[ "$here" != "${BASH_SOURCE[0]}" ] || here=.
runner=${CANOPY_BIN:-$here/../build/bin}/stagerun
[ -x "$runner" ] || { echo "stage.sh: error: $runner is not built (cmake --build build --target stagerun)" >&2; exit 127; }
# (the resources file beside this script, as before, unless the caller names one)
export CANOPY_RESOURCES=${CANOPY_RESOURCES:-$here/../share/resources.ini}
exec "$runner" "$@"
