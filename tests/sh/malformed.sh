#!/bin/sh
# Malformed scenes through the limen program (tests/malformed/cases.txt lists them): each must
# end by itself (within 20 s), with exit status 1 rather than a signal, print exactly its
# one line on stderr ("limen: FILE:LINE: message", or "limen: FILE: message" where no line
# applies), and write no image.
. tests/sh/lib.sh

# check_scene FILE ARGS EXPECTED PENDING
check_scene() {
    file=tests/malformed/$1 args=$2 pending=$4
    want=$(printf '%s' "$3" | sed "s|FILE|$file|g")
    rm -f "$TMP"/out*.png
    # shellcheck disable=SC2086  # ARGS are words
    timeout 20 "$LIMEN" render "$file" -o "$TMP/out.png" --size 64x48 $args \
        > "$TMP/stdout" 2> "$TMP/stderr"
    rc=$?
    if [ $rc -eq 124 ]; then echo "hung: killed after 20 s"; return 1; fi
    if [ $rc -ge 128 ]; then echo "crashed: exit status $rc"; cat "$TMP/stderr"; return 1; fi
    if ls "$TMP"/out*.png > /dev/null 2>&1; then
        [ -n "$pending" ] || { echo "wrote an image: $(ls "$TMP"/out*.png)"; return 1; }
        echo "wrote an image (pending: $pending)"; return 0
    fi
    got=$(cat "$TMP/stderr")
    if [ $rc -ne 1 ] || [ "$(wc -l < "$TMP/stderr")" -ne 1 ] || [ "$got" != "$want" ]; then
        if [ -n "$pending" ]; then echo "pending: $pending"; return 0; fi
        echo "exit status $rc, stderr:"; cat "$TMP/stderr"; echo "expected exit status 1 and:"
        echo "$want"
        return 1
    fi
    [ -z "$pending" ] || echo "passes now: drop the pending mark"
}

count=0
while IFS= read -r line; do
    case "$line" in '#'* | '') continue ;; esac
    # FILE | ARGS | EXPECTED [| pending: WHY]
    file=${line%% | *} rest=${line#* | }
    args=${rest%% | *} rest=${rest#* | }
    want=${rest%% | pending: *} pending=
    case "$rest" in *' | pending: '*) pending=${rest#* | pending: } ;; esac
    [ "$args" = - ] && args=
    if [ ! -f "tests/malformed/$file" ]; then
        echo "FAIL missing tests/malformed/$file"; failed=$((failed + 1)); continue
    fi
    t_ok "$file${pending:+ (pending)}" check_scene "$file" "$args" "$want" "$pending"
    if [ -n "$pending" ]; then sed 's/^/     /' "$TMP/out"; fi
    count=$((count + 1))
done < tests/malformed/cases.txt
# every scene file is listed
for f in tests/malformed/*.lua; do
    grep -q "^$(basename "$f") |" tests/malformed/cases.txt ||
        { echo "FAIL $f is not in tests/malformed/cases.txt"; failed=$((failed + 1)); }
done
[ "$count" -ge 30 ] || { echo "FAIL only $count malformed scenes"; failed=$((failed + 1)); }
t_done
