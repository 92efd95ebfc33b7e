# Shared helpers for the shell tests: t_ok NAME CMD... counts a pass when CMD succeeds.
B=${1:-build}
LIMEN="$B/limen"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/limen-test.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
passed=0 failed=0
t_ok() {
    name=$1; shift
    if "$@" >"$TMP/out" 2>&1; then
        passed=$((passed + 1)); echo "ok   $name"
    else
        failed=$((failed + 1)); echo "FAIL $name"; sed 's/^/     /' "$TMP/out" | head -20
    fi
}
t_done() {
    echo "$passed passed, $failed failed"
    [ $failed -eq 0 ]
}
