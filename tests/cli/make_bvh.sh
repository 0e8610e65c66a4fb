#!/usr/bin/env bash
# Writes a BVH file to stdout, for the regression tests:
#   make_bvh.sh deep N   a chain of N nested joints
#   make_bvh.sh wide N   a root with N - 1 sibling children
#     (one Zrotation channel per joint, 2 frames)
#   make_bvh.sh one_rotation JOINT FILE
#                        FILE with JOINT's rotation channels cut to its first
#                        one (the other rotation values dropped from every frame)
set -euo pipefail
shape=$1
if [[ $shape == one_rotation ]]; then
  awk -v joint="$2" '
    { sub(/\r$/, "") }
    data { line = ""; for (k = 1; k <= NF; ++k) if (!(k in drop)) line = line (line == "" ? "" : " ") $k; print line; next }
    /^Frame Time/ { data = 1 }
    ($1 == "ROOT" || $1 == "JOINT") && $2 == joint { pending = 1 }
    $1 == "CHANNELS" {
      if (pending) {
        kept = ""; n = 0; rotations = 0
        for (k = 3; k <= NF; ++k) {
          if ($k ~ /rotation$/ && rotations++ > 0) { drop[columns + k - 2] = 1; continue }
          kept = kept " " $k; ++n
        }
        sub(/CHANNELS.*/, "CHANNELS " n kept)
        pending = 0
      }
      columns += $2
    }
    { print }' "$3"
  exit
fi
n=$2
awk -v shape="$shape" -v n="$n" 'BEGIN {
  print "HIERARCHY"; print "ROOT j0"; print "{"; print "OFFSET 0 0 0"; print "CHANNELS 1 Zrotation"
  for (k = 1; k < n; ++k) {
    print "JOINT j" k; print "{"; print "OFFSET 0 1 0"; print "CHANNELS 1 Zrotation"
    if (shape == "wide") print "}"
  }
  if (shape == "deep") for (k = 1; k < n; ++k) print "}"
  print "}"; print "MOTION"; print "Frames: 2"; print "Frame Time: 0.0333333"
  for (f = 0; f < 2; ++f) { line = ""; for (k = 0; k < n; ++k) line = line (k ? " " : "") f; print line }
}'
