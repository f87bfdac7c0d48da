#!/bin/bash
# usermb-crop.sh SIZE INI [CROP_LENGTH]: the rangetrace options that fit one user mesh in the
# crop box and the image (mk/usermb.mk, docs/decisions/user-modelbase.md). SIZE is meshsize's
# "length width height" (m), INI the rangetrace parameters (size, spacing, crop-length,
# crop-width, crop-height). A mesh that fits INI's crop box with 0.5 m to spare on every side
# gets no option (its render is the one verify-modelbase would make); otherwise each crop side
# it overflows becomes the mesh's extent + 1 m, rounded up to whole metres (CROP_LENGTH, e.g.
# 14m, replaces the length's choice), and the image grows (--size) when the box's diagonal +
# 2 m no longer fits size x spacing. Prints the options on one line (possibly empty). A mesh
# whose render would need more than rangetrace's 8192 pixels a side (a mesh in mm or cm read as
# metres) is refused, exit 2, with the hint MESH_UNITS, and so is one with no side of 0.5 m (a
# mesh in metres read as mm or cm).
set -euo pipefail
size=$1 ini=$2 crop_length=${3:-}
read -r L W H <"$size"
awk -v L="$L" -v W="$W" -v H="$H" -v over="$crop_length" -v file="$size" '
  function metres(v,   n) {  # "10m", "4000mm", "250cm" or a bare number (m)
    gsub(/[ \t"]/, "", v); n = v + 0
    if (v ~ /mm$/) return n / 1000; if (v ~ /cm$/) return n / 100; return n
  }
  function up(x) { return x == int(x) ? x : int(x) + 1 }
  /^[ \t]*[#;]/ { next }
  /=/ { k = $0; sub(/=.*/, "", k); gsub(/[ \t]/, "", k); v = substr($0, index($0, "=") + 1); ini[k] = v }
  END {
    cl = metres(ini["crop-length"]); cw = metres(ini["crop-width"]); ch = metres(ini["crop-height"])
    sp = metres(ini["spacing"]); sz = ini["size"] + 0
    if (cl <= 0 || cw <= 0 || ch <= 0 || sp <= 0 || sz <= 0) { print "usermb-crop.sh: no crop box, size or spacing in the ini" > "/dev/stderr"; exit 2 }
    # A vehicle under 0.5 m long as read (stop 71, review F17): a mesh in metres given
    # MESH_UNITS=mm or cm renders a 5 mm object, which the chain takes for bare ground and then
    # fails on ("all samples are coplanar"); refused before the render, like the other direction.
    big = L; if (W > big) big = W; if (H > big) big = H
    if (big < 0.5) {
      printf "usermb-crop.sh: %s: the mesh measures %s x %s x %s m as read (MESH_UNITS, MESH_UP): no side reaches 0.5 m, too small for a vehicle: a mesh in metres given MESH_UNITS=mm or cm? (metres are the default)\n", file, L, W, H > "/dev/stderr"
      exit 2
    }
    opts = ""
    if (over != "") { nl = metres(over); if (nl <= 0) { print "usermb-crop.sh: MESH_CROP_LENGTH=" over " is not a length" > "/dev/stderr"; exit 2 } }
    else nl = (L + 1 > cl) ? up(L + 1) : cl
    nw = (W + 1 > cw) ? up(W + 1) : cw
    nh = (H + 1 > ch) ? up(H + 1) : ch
    if (nl != cl || over != "") opts = opts " --crop-length " nl "m"
    if (nw != cw) opts = opts " --crop-width " nw "m"
    if (nh != ch) opts = opts " --crop-height " nh "m"
    need = up((sqrt(nl * nl + nw * nw + nh * nh) + 2) / sp)
    if (need > 8192) {  # rangetrace renders at most 8192 pixels a side: a mesh in mm or cm read as m
      printf "usermb-crop.sh: %s: the mesh measures %s x %s x %s m as read (MESH_UNITS, MESH_UP): its render at %g mm a pixel needs %d pixels a side, over the 8192 rangetrace draws; a mesh in millimetres or centimetres needs MESH_UNITS=mm or MESH_UNITS=cm\n", file, L, W, H, sp * 1000, need > "/dev/stderr"
      exit 2
    }
    if (need > sz) opts = opts " --size " need
    sub(/^ /, "", opts); print opts
  }' "$ini"
