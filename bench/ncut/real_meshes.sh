#!/usr/bin/env bash
# Builds real vehicle meshes with the pipeline binaries (rangetrace, addnoise, fitvox, cocone
# from any build-*/bin) into DIR, then runs ncut_bench on them (timing, both exponents).
# Usage: bench/ncut/real_meshes.sh DIR [objects...]   (default objects: sedan obj1 tank)
set -eu
dir=$1; shift
objects=${*:-sedan obj1 tank}
root=$(cd "$(dirname "$0")/../.." && pwd)
find_bin() { ls "$root"/build*/bin/"$1" 2>/dev/null | head -1; }
for t in rangetrace addnoise fitvox cocone ncut_bench; do
  [ -n "$(find_bin $t)" ] || { echo "missing $t in build*/bin" >&2; exit 1; }
done
mkdir -p "$dir"
meshes=()
for o in $objects; do
  for scene in unoccluded circle; do
    scan="$dir/$o-$scene.pcd"
    [ -s "$scan" ] || "$(find_bin rangetrace)" -q --model "$o" --scene "$scene" -o "$scan"
    for sigma in 0 8 16; do
      [ "$scene" = unoccluded ] && [ "$sigma" != 0 ] && continue
      m="$dir/$o-$scene-$sigma.ply"
      if [ ! -s "$m" ]; then
        "$(find_bin addnoise)" -q --sigma "${sigma}mm" -i "$scan" |
          "$(find_bin fitvox)" -q | "$(find_bin cocone)" -q -o "$m"
      fi
      meshes+=("$m")
    done
  done
done
"$(find_bin ncut_bench)" --quick "${meshes[@]}"
