#!/usr/bin/env bash
# Writes a BVH file with N joints to stdout, for the regression tests:
#   make_bvh.sh deep N   a chain of N nested joints
#   make_bvh.sh wide N   a root with N - 1 sibling children
# One Zrotation channel per joint, 2 frames.
set -euo pipefail
shape=$1 n=$2
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
