#!/usr/bin/env bash
# Long inputs under 1 MB for the regression tests of the work and memory
# limits, to stdout:
#   make_long.sh keys N SKELETON  a flight key set of N keys 0.01 s apart
#   make_long.sh frames N         a BVH of one joint with one channel, N frames
set -euo pipefail
what=$1 n=$2
case $what in
  keys)
    awk -v n="$n" -v skeleton="$3" 'BEGIN {
      printf "{\"skeleton\": \"%s\", \"keys\": [", skeleton
      for (k = 0; k < n; ++k) printf "%s{\"time\": %.2f, \"root_position\": [0, 1, 0]}", (k ? ", " : ""), k * 0.01
      print "]}"
    }' ;;
  frames)
    awk -v n="$n" 'BEGIN {
      print "HIERARCHY"; print "ROOT j0"; print "{"; print "OFFSET 0 0 0"; print "CHANNELS 1 Xposition"
      print "End Site"; print "{"; print "OFFSET 0 1 0"; print "}"; print "}"
      print "MOTION"; print "Frames: " n; print "Frame Time: 0.0083333"
      for (f = 0; f < n; ++f) printf "%.2f\n", 1 + (f * 37 % 1000) / 100
    }' ;;
  *) echo "make_long.sh: keys N SKELETON or frames N" >&2; exit 2 ;;
esac
