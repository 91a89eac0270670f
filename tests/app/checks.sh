# The checks shared by the shell tests of the commands (results_test.sh, trace_test.sh), to be
# sourced after `svetlo` is set: a scratch folder, pass and fail counts, and
#   check NAME COMMAND...           passes when the command succeeds;
#   expect_error NAME WHERE CODE ARGS...   svetlo ARGS exits CODE with one stderr line, in the
#                                          contract's format, naming WHERE;
#   bunny_mesh SCENES WHAT          whether bunny.json's mesh, the workplace's public data
#                                   (../shared/data beside the repository), is there; where
#                                   it is not, says that WHAT is skipped;
#   summary                         prints the counts and fails when any check did.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
pass() { passed=$((passed + 1)); }
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
check() {
    local name=$1
    shift
    if "$@" > "$work/check.out" 2>&1; then pass; else fail "$name: $(head -c 400 "$work/check.out")"; fi
}
expect_error() {
    local name=$1 where=$2 code=$3
    shift 3
    "$svetlo" "$@" > "$work/stdout" 2> "$work/stderr"
    local rc=$?
    if [ $rc -ne "$code" ]; then fail "$name: exit $rc, not $code: $(cat "$work/stderr")"; return; fi
    if [ "$(wc -l < "$work/stderr")" -ne 1 ]; then fail "$name: $(cat "$work/stderr")"; return; fi
    if ! grep -Eq "^svetlo: error: [^:]+: .*${where}" "$work/stderr"; then
        fail "$name: '$(cat "$work/stderr")' does not name '$where'"; return
    fi
    pass
}
bunny_mesh() {
    [ -f "$1/../../shared/data/bunny/bun_zipper.ply" ] && return 0
    echo "skipped: $2 (the bunny's mesh, ../shared/data/bunny, is absent)"
    return 1
}
summary() {
    echo "$passed passed, $failed failed"
    [ "$failed" -eq 0 ]
}
