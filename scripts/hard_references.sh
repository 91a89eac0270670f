#!/usr/bin/env bash
# The converged references of the hard scenes (docs/path.md, "Hard scenes"): each scene
# rendered by svetlo's path tracer, unguided, at 160 x 120 with many samples and seed 7919
# (the races render seeds 0 and 1), into scenes/references/NAME.exr with its provenance
# (`svetlo info` shows how it was made; `svetlo reproduce` makes it again, bit for bit).
# Usage: scripts/hard_references.sh [SVETLO] (default build/svetlo). About 10 minutes on
# two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
svetlo=${1:-$root/build/svetlo}
out=$root/scenes/references
mkdir -p "$out"
reference() {  # NAME SPP
    "$svetlo" render "$root/scenes/$1.json" -W 160 -H 120 --spp "$2" --seed 7919 \
        --set render.guiding=false -q -o "$out/$1.exr"
    echo "$out/$1.exr: $2 spp"
}
reference door_ajar 16384
reference lamp_shade 8192
reference glass_caustic 4096
