#!/usr/bin/env bash
# trials.sh BIN OUTDIR MODELBASE LIST: development/calibration trials for verify, never the
# experiment's. LIST has one trial per line: "<model> <scene> <noise mm> <heading deg> <x> <y> <seed>"
# (<model> a share/models name, a clutter-verify/<name>.inc path or a mesh file, whose stem
# is then the model's name in the modelbase). RANGETRACE_ARGS adds rangetrace options. Each trial runs
# rangetrace -> addnoise -> fitvox -> cocone -> ncut -> gmatch -> verify into OUTDIR/<line no>/
# (kept; reruns redo only gmatch and verify) and prints one CSV row per trial:
# trial,model,scene,noise,heading,x,y,seed,gmatch_top,gmatch_margin,verify_model,confidence,
# best_score,best_explained,best_violation,true_score,heading_err_deg,pos_err_m,verify_s,
# best_model,second_score,true_flipped
set -u
bin=$1 out=$2 mb=$3 list=$4
shift 4
extra=("$@")   # extra verify options
src=$(cd "$(dirname "$0")/../.." && pwd)
n=0
while read -r model scene noise heading x y seed; do
  [ -z "${model:-}" ] && continue
  case $model in \#*) continue;; esac
  n=$((n + 1))
  d=$out/$n
  mkdir -p "$d"
  m=$model
  case $model in clutter-verify/*) m=$src/share/models/$model.inc;; esac
  sc=$scene
  [ -f "$src/share/scenes/$scene.scene" ] && sc=$src/share/scenes/$scene.scene
  if [ ! -s "$d/segments.json" ]; then
    { "$bin/rangetrace" -q ${RANGETRACE_ARGS:-} --model "$m" --scene "$sc" --heading "${heading}deg" --position "$x,$y" \
        --seed "$seed" --threads 2 -o "$d/raw.pcd" &&
      "$bin/addnoise" -q --sigma "${noise}mm" --seed "$seed" -i "$d/raw.pcd" -o "$d/scan.pcd" &&
      "$bin/fitvox" -q --config "$src/share/params/fitvox.ini" -i "$d/scan.pcd" -o "$d/samples.pcd" &&
      "$bin/cocone" -q --config "$src/share/params/cocone.ini" -i "$d/samples.pcd" -o "$d/mesh.ply" &&
      "$bin/ncut" -q --config "$src/share/params/ncut.ini" --seed "$seed" -i "$d/mesh.ply" \
        -o "$d/segments.json"; } 2>"$d/pipeline.log" || { echo "$n,$model,FAILED" >&2; continue; }
  fi
  # gmatch and verify always re-run (cheap): GMATCH_ARGS ablates gmatch options.
  "$bin/gmatch" -q --config "$src/share/params/gmatch.ini" ${GMATCH_ARGS:-} -i "$d/segments.json" \
    --modelbase "$mb" -o "$d/match.json" 2>"$d/gmatch.log" || { echo "$n,$model,GMATCH FAILED" >&2; continue; }
  t0=$(date +%s.%N)
  "$bin/verify" -q --config "$src/share/params/verify.ini" "${extra[@]}" -i "$d/match.json" \
    --points "$d/samples.pcd" --segments "$d/segments.json" --modelbase "$mb" -o "$d/verdict.json" \
    2>"$d/verify.log" || { echo "$n,$model,VERIFY FAILED" >&2; continue; }
  t1=$(date +%s.%N)
  python3 - "$d" "$n" "$model" "$scene" "$noise" "$heading" "$x" "$y" "$seed" "$t0" "$t1" <<'PY'
import json, math, sys
d, n, model, scene, noise, heading, x, y, seed, t0, t1 = sys.argv[1:]
if "/" in model and not model.startswith("clutter"):  # a mesh file: its stem names the model
    model = model.rsplit("/", 1)[-1].rsplit(".", 1)[0]
m = json.load(open(d + "/match.json"))
v = json.load(open(d + "/verdict.json"))
top = m["models"][0]["model"]
margin = m["models"][0]["score"] - (m["models"][1]["score"] if len(m["models"]) > 1 else 0)
hs = v["hypotheses"]
best = max(hs, key=lambda h: h["score"])
second = max([h["score"] for h in hs if h is not best] + [0.0])
true = [h for h in hs if h["model"] == model]
ts = true[0]["score"] if true else -1
herr = perr = -1
if true:
    h = true[0]
    dh = (h["pose"]["heading_deg"] - float(heading) + 180) % 360 - 180
    herr = abs(dh)
    t = h["pose"]["translation"]
    perr = math.hypot(t[0] - float(x), t[1] - float(y))
print(",".join(str(s) for s in [n, model, scene, noise, heading, x, y, seed, top, "%.4f" % margin,
      v["model"] or "none", "%.4f" % v["confidence"], "%.4f" % best["score"], "%.4f" % best["explained"],
      "%.4f" % best["free_space_violation"], "%.4f" % ts, "%.3f" % herr, "%.4f" % perr,
      "%.3f" % (float(t1) - float(t0)), best["model"], "%.4f" % second,
      int(true[0]["flipped"]) if true else -1]))
PY
done <"$list"
