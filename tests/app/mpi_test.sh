#!/usr/bin/env bash
# One image on many processes (docs/distributed.md), driven as a user would through mpirun:
# for every engine, -np 1, 2 and 3 with 1 and 2 threads write the bytes of the plain program;
# the provenance says how many processes; a slowed rank still gets the image right; a rank
# killed mid-render ends the job within 10 s, naming the rank; the flags that need one process
# are refused with one line; checkpoints of tiles and of the radiosity solve resume on another
# number of processes, bit for bit.
# Usage: mpi_test.sh SVETLO SCENES_DIR MPIRUN
set -u
svetlo=$1
scenes=$2
mpirun=$3
source "$(dirname "$0")/checks.sh"
# As root in a container OpenMPI wants --allow-run-as-root; more ranks than cores need
# --oversubscribe.
run=("$mpirun" --oversubscribe --allow-run-as-root)
cornell="$scenes/cornell.json"
size=(-W 72 -H 40 --spp 2)

# The progressive radiosity solve is split among the ranks (the hierarchical one is repeated).
progressive=(--set render.radiosity.solver=progressive --set render.radiosity.element_size=0.3
             --set render.radiosity.adaptive=0)
for engine in raster whitted path radiosity radiosity_progressive; do
    scene=$cornell
    extra=(-e "$engine")
    [ "$engine" = radiosity ] && scene="$scenes/cornell_radiosity.json"
    [ "$engine" = radiosity_progressive ] && scene="$scenes/cornell_radiosity.json" && extra=("${progressive[@]}")
    "$svetlo" render "$scene" "${extra[@]}" "${size[@]}" -q -o "$work/one.pfm"
    for np in 1 2 3; do
        for threads in 1 2; do
            rm -f "$work/many.pfm"
            "${run[@]}" -np "$np" "$svetlo" render "$scene" "${extra[@]}" "${size[@]}" -t "$threads" \
                -o "$work/many.pfm" > "$work/out.txt" 2>&1
            check "$engine -np $np -t $threads: the plain program's bytes" cmp "$work/one.pfm" "$work/many.pfm"
        done
    done
    check "$engine: the provenance counts 3 processes" grep -q '"processes":3' "$work/many.pfm.json"
    if [ "$engine" = radiosity_progressive ]; then
        check "the solve's exchange is reported" grep -q "MiB exchanged in the setup" "$work/out.txt"
    fi
done
check "one process: the provenance counts 1" grep -q '"processes":1' "$work/one.pfm.json"

# A crop and AOVs, across processes: the same bytes.
"$svetlo" render "$cornell" -e path "${size[@]}" --crop 10,60,5,33 -q -o "$work/one.pfm" \
    --aov depth="$work/one_depth.pfm" --aov bvh_cost="$work/one_cost.pfm"
"${run[@]}" -np 3 "$svetlo" render "$cornell" -e path "${size[@]}" --crop 10,60,5,33 -q \
    -o "$work/many.pfm" --aov depth="$work/many_depth.pfm" --aov bvh_cost="$work/many_cost.pfm"
check "a crop on 3 processes" cmp "$work/one.pfm" "$work/many.pfm"
check "its depth AOV" cmp "$work/one_depth.pfm" "$work/many_depth.pfm"
check "its bvh_cost AOV" cmp "$work/one_cost.pfm" "$work/many_cost.pfm"
"$svetlo" render "$scenes/shadows.json" -W 64 -H 40 -q -o "$work/one.pfm" \
    --aov shadow_map="$work/one_map.pfm"
"${run[@]}" -np 2 "$svetlo" render "$scenes/shadows.json" -W 64 -H 40 -q -o "$work/many.pfm" \
    --aov shadow_map="$work/many_map.pfm"
check "a shadow map (not the film's size) on 2 processes" cmp "$work/one_map.pfm" "$work/many_map.pfm"

# A rank three times slower: the image is the same, and the other takes most tiles.
SVETLO_TEST_SLOW_RANK=1:3 "${run[@]}" -x SVETLO_TEST_SLOW_RANK -np 2 "$svetlo" render "$cornell" \
    -e whitted -W 160 -H 96 -t 1 -o "$work/slow.pfm" > "$work/slow.txt" 2>&1
"$svetlo" render "$cornell" -e whitted -W 160 -H 96 -q -o "$work/fast.pfm"
check "a slow rank: the same image" cmp "$work/slow.pfm" "$work/fast.pfm"
check "a slow rank gets fewer tiles" python3 -c "
import re
t = open('$work/slow.txt').read()
m = re.search(r'(\d+) tiles \((\d+) on rank 0\)', t)
assert m and int(m.group(2)) > int(m.group(1)) // 2, t"

# A rank killed mid-render: the job ends within 10 s, and says which rank.
"${run[@]}" -np 2 "$svetlo" render "$cornell" -e path -W 256 -H 256 --spp 100000 -t 1 -q \
    -o "$work/killed.pfm" > "$work/killed.txt" 2>&1 &
job=$!
sleep 3
victim=""
for pid in $(pgrep -f "svetlo render $cornell -e path -W 256 -H 256 --spp 100000"); do
    if tr '\0' '\n' < /proc/$pid/environ 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then victim=$pid; fi
done
check "found rank 1" test -n "$victim"
[ -n "$victim" ] && kill -9 "$victim"
for _ in $(seq 1 100); do kill -0 $job 2>/dev/null || break; sleep 0.1; done
if kill -0 $job 2>/dev/null; then
    fail "the job still runs 10 s after rank 1 was killed"
    kill -9 $job
else
    wait $job
    check "the killed job exits non-zero" test $? -ne 0
    check "the job names the killed rank" grep -q "rank 1" "$work/killed.txt"
    check "no image from a killed job" test ! -e "$work/killed.pfm"
fi

# SIGINT to mpirun reaches every rank: no tile is begun after it, the tiles in progress end
# their pass, and rank 0 writes the image, marked interrupted.
"${run[@]}" -np 2 "$svetlo" render "$cornell" -e path -W 128 -H 128 --spp 100000 -t 1 -q \
    -o "$work/int.pfm" > "$work/int.txt" 2>&1 &
job=$!
sleep 3
pkill -INT -f "^$mpirun.*-W 128 -H 128 --spp 100000" || kill -INT $job
for _ in $(seq 1 100); do kill -0 $job 2>/dev/null || break; sleep 0.1; done
if kill -0 $job 2>/dev/null; then fail "SIGINT: the job still runs after 10 s"; kill -9 $job; fi
wait $job
check "SIGINT under mpirun writes the image, marked interrupted" \
    grep -q '"interrupted":true' "$work/int.pfm.json"

# What needs one process, refused on every rank with one line from rank 0.
"${run[@]}" -np 2 "$svetlo" render "$cornell" -e path --time 1 -o "$work/x.pfm" > "$work/out.txt" 2>&1
check "--time under mpirun: one line" test "$(grep -c '^svetlo: error: .*--time: renders on one process only' "$work/out.txt")" = 1

# --checkpoint under mpirun. The path tracer's tiles: killed (SIGKILL to mpirun) after a save on
# 2 processes, resumed on 3, the plain program's bytes.
tiles=(render "$cornell" -e path -W 160 -H 96 --spp 256)
"$svetlo" "${tiles[@]}" -t 2 -q -o "$work/plain.pfm"
"${run[@]}" -np 2 "$svetlo" "${tiles[@]}" -t 1 -q --checkpoint "$work/tiles.ck" -o "$work/tiles.pfm" \
    > "$work/out.txt" 2>&1 &
job=$!
for _ in $(seq 1 300); do [ -s "$work/tiles.ck" ] && break; sleep 0.05; done
kill -9 $job 2> /dev/null
pkill -9 -f "svetlo render $cornell -e path -W 160 -H 96 --spp 256" 2> /dev/null
wait $job 2> /dev/null
check "tiles: a checkpoint saved before the kill" test -s "$work/tiles.ck"
check "tiles: no image from the killed job" test ! -e "$work/tiles.pfm"
"${run[@]}" -np 3 "$svetlo" "${tiles[@]}" -t 1 --checkpoint "$work/tiles.ck" -o "$work/tiles.pfm" > "$work/out.txt" 2>&1
check "tiles: the resumed job says so" grep -q "resumed from .* with [0-9]* tiles done" "$work/out.txt"
check "tiles: resumed on 3 equals the plain program" cmp "$work/plain.pfm" "$work/tiles.pfm"
# The radiosity solve: SIGINT on 2 processes writes the solution as it stands; resumed on 3,
# the plain program's bytes. A checkpoint of one process resumes on many, and back.
solve=(render "$scenes/cornell_radiosity.json" -W 64 -H 64 -t 1 "${progressive[@]}"
       --set render.radiosity.element_size=0.08)
"$svetlo" "${solve[@]}" -q -o "$work/plain.pfm"
"${run[@]}" -np 2 "$svetlo" "${solve[@]}" -q --checkpoint "$work/solve.ck" -o "$work/solve.pfm" \
    > "$work/out.txt" 2>&1 &
job=$!
for _ in $(seq 1 300); do [ -s "$work/solve.ck" ] && break; sleep 0.05; done
# SIGINT to the ranks themselves, as Ctrl-C in a terminal sends it to the whole foreground
# group. (mpirun of OpenMPI 4.1 answers its own SIGINT with SIGTERM to the ranks and SIGKILL one
# second later, odls_base_sigkill_timeout: the solve's last shot and the display pass of a
# 2-core machine take longer, and the ranks were killed before writing. The tiles above end
# within that second.)
pkill -INT -f "^$svetlo render $scenes/cornell_radiosity.json -W 64 -H 64" || kill -INT $job
wait $job
check "solve: SIGINT writes the image, marked interrupted" grep -q '"interrupted":true' "$work/solve.pfm.json"
"${run[@]}" -np 3 "$svetlo" "${solve[@]}" --checkpoint "$work/solve.ck" -o "$work/solve.pfm" > "$work/out.txt" 2>&1
check "solve: the resumed job says so" grep -q "resumed from .* after shot" "$work/out.txt"
check "solve: resumed on 3 equals the plain program" cmp "$work/plain.pfm" "$work/solve.pfm"
"$svetlo" "${solve[@]}" -q --checkpoint "$work/solve.ck" -o "$work/again.pfm"
check "solve: its checkpoint gives the image again on one process" cmp "$work/plain.pfm" "$work/again.pfm"
# A checkpoint of one process's path render holds passes, not tiles: refused under mpirun.
"$svetlo" render "$cornell" -e path -W 64 -H 40 --spp 2 -q --checkpoint "$work/one.ck" -o "$work/x.pfm"
"${run[@]}" -np 2 "$svetlo" render "$cornell" -e path -W 64 -H 40 --spp 2 --checkpoint "$work/one.ck" \
    -o "$work/y.pfm" > "$work/out.txt" 2>&1
check "one process's checkpoint under mpirun: one line" \
    test "$(grep -c '^svetlo: error: .*--checkpoint: was saved by a render of another' "$work/out.txt")" = 1
summary
