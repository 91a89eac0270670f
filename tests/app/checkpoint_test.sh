#!/usr/bin/env bash
# --checkpoint (docs/distributed.md), driven as a user would: a path render killed (SIGKILL)
# after some passes and run again with the same file equals an uninterrupted one, byte for
# byte, with and without the photon map; so does a radiosity solve; SIGINT writes the passes
# done and the run resumes; a checkpoint of another scene or other settings, a corrupt,
# truncated or foreign file, and an engine or solver that keeps none are refused with one line,
# and nothing is written.
# Usage: checkpoint_test.sh SVETLO SCENES_DIR
set -u
svetlo=$1
scenes=$2
source "$(dirname "$0")/checks.sh"

# kill_after_a_pass SIGNAL FILE ARGS...: starts the render, sends SIGNAL once FILE holds a
# pass, and waits for it.
kill_after_a_pass() {
    local signal=$1 file=$2
    shift 2
    "$svetlo" "$@" -q --checkpoint "$file" &
    local pid=$!
    # 20 s at most for the first save (200 s under an emulator, SVETLO_EMULATED).
    local tries=1000
    [ "${SVETLO_EMULATED:-0}" = 1 ] && tries=10000
    for _ in $(seq 1 $tries); do [ -s "$file" ] && break; sleep 0.02; done
    sleep 0.3
    kill "-$signal" $pid 2> /dev/null
    wait $pid 2> /dev/null
}

for scene in cornell caustics; do
    args=(render "$scenes/$scene.json" -e path -W 160 -H 120 --spp 48)
    "$svetlo" "${args[@]}" -q -o "$work/$scene.pfm"
    rm -f "$work/resumed.pfm"
    kill_after_a_pass KILL "$work/$scene.ck" "${args[@]}" -o "$work/resumed.pfm"
    check "$scene: killed with a checkpoint saved" test -s "$work/$scene.ck"
    check "$scene: nothing written by the killed run" test ! -e "$work/resumed.pfm"
    "$svetlo" "${args[@]}" --checkpoint "$work/$scene.ck" -o "$work/resumed.pfm" 2> "$work/err.txt"
    check "$scene: the resumed run says so" grep -q "resumed from .* after pass" "$work/err.txt"
    check "$scene: resumed equals uninterrupted" cmp "$work/$scene.pfm" "$work/resumed.pfm"
    # Run once more: every pass is in the file already, the same image again.
    "$svetlo" "${args[@]}" -q --checkpoint "$work/$scene.ck" -o "$work/again.pfm"
    check "$scene: a finished checkpoint gives the image again" cmp "$work/$scene.pfm" "$work/again.pfm"
done

# SIGINT: the passes done are written (marked interrupted), and the run resumes from them.
args=(render "$scenes/cornell.json" -e path -W 160 -H 120 --spp 48)
kill_after_a_pass INT "$work/int.ck" "${args[@]}" -o "$work/int.pfm"
check "SIGINT writes the passes done" grep -q '"interrupted":true' "$work/int.pfm.json"
"$svetlo" "${args[@]}" -q --checkpoint "$work/int.ck" -o "$work/int.pfm"
check "after SIGINT, resumed equals uninterrupted" cmp "$work/cornell.pfm" "$work/int.pfm"

# The radiosity solve (progressive): killed after a save, it resumes with its shots and rows and
# ends in the uninterrupted image; a finished one gives the image again at once.
radiosity=(render "$scenes/cornell_radiosity.json" -W 64 -H 64 -t 2
           --set render.radiosity.solver=progressive --set render.radiosity.element_size=0.08
           --set render.radiosity.adaptive=0)
"$svetlo" "${radiosity[@]}" -q -o "$work/radiosity.pfm"
kill_after_a_pass KILL "$work/radiosity.ck" "${radiosity[@]}" -o "$work/resumed.pfm"
check "radiosity: killed with a checkpoint saved" test -s "$work/radiosity.ck"
"$svetlo" "${radiosity[@]}" --checkpoint "$work/radiosity.ck" -o "$work/resumed.pfm" 2> "$work/err.txt"
check "radiosity: the resumed run says so" grep -q "resumed from .* after shot" "$work/err.txt"
check "radiosity: resumed equals uninterrupted" cmp "$work/radiosity.pfm" "$work/resumed.pfm"
kill_after_a_pass INT "$work/radiosity_int.ck" "${radiosity[@]}" -o "$work/int.pfm"
check "radiosity: SIGINT writes the solution as it stands" grep -q '"interrupted":true' "$work/int.pfm.json"
"$svetlo" "${radiosity[@]}" -q --checkpoint "$work/radiosity_int.ck" -o "$work/int.pfm"
check "radiosity: after SIGINT, resumed equals uninterrupted" cmp "$work/radiosity.pfm" "$work/int.pfm"

# Refusals: one line naming --checkpoint, and no image.
ck="$work/cornell.ck"
expect_error "another scene" "--checkpoint: was saved by a render of another scene or other settings" 1 \
    render "$scenes/spheres.json" -e path -W 160 -H 120 --spp 48 --checkpoint "$ck" -o "$work/x.pfm"
expect_error "other settings" "--checkpoint: was saved by a render of another scene" 1 \
    "${args[@]}" --seed 5 --checkpoint "$ck" -o "$work/x.pfm"
cp "$ck" "$work/corrupt.ck"
printf '\x55' | dd of="$work/corrupt.ck" bs=1 seek=200 conv=notrunc 2> /dev/null
expect_error "a corrupt checkpoint" "--checkpoint: is corrupt or truncated" 1 \
    "${args[@]}" --checkpoint "$work/corrupt.ck" -o "$work/x.pfm"
head -c 1000 "$ck" > "$work/short.ck"
expect_error "a truncated checkpoint" "--checkpoint: is corrupt or truncated" 1 \
    "${args[@]}" --checkpoint "$work/short.ck" -o "$work/x.pfm"
echo "not a checkpoint" > "$work/foreign.ck"
expect_error "a foreign file" "--checkpoint: is not a svetlo checkpoint" 1 \
    "${args[@]}" --checkpoint "$work/foreign.ck" -o "$work/x.pfm"
expect_error "an engine that keeps none" "--checkpoint: needs an engine that keeps one .path or radiosity.; whitted does not" 1 \
    render "$scenes/cornell.json" -e whitted --checkpoint "$work/w.ck" -o "$work/x.pfm"
expect_error "a radiosity solver that keeps none" "--checkpoint: the radiosity solve is checkpointed by the progressive solver only" 1 \
    render "$scenes/cornell_radiosity.json" --checkpoint "$work/h.ck" -o "$work/x.pfm"
expect_error "a path checkpoint for a radiosity solve" "--checkpoint: was saved by a render of another scene" 1 \
    "${radiosity[@]}" --checkpoint "$ck" -o "$work/x.pfm"
expect_error "an unwritable checkpoint" "--checkpoint: cannot write" 1 \
    "${args[@]}" --checkpoint "$work/no/such/dir/ck" -o "$work/x.pfm"
check "no image from a refused run" test ! -e "$work/x.pfm"
check "a refused checkpoint is left as it was" cmp "$work/foreign.ck" <(echo "not a checkpoint")
summary
