#!/bin/sh
# inspect_cli_test.sh PNB_INSPECT PNB_MAKE_SAMPLE WORK_DIR
#
# The pnb-inspect executable's own layer, which inspect_test.cpp cannot reach in-process:
# argument parsing, --help, and the documented exit codes (0 ok, 1 usage, 2 input error).
set -u
inspect=${1:?usage: inspect_cli_test.sh PNB_INSPECT PNB_MAKE_SAMPLE WORK_DIR}
make_sample=${2:?}
dir=${3:?}
status=0

mkdir -p "$dir"
sample="$dir/box_room.pnb"
"$make_sample" "$sample" >/dev/null || { echo "pnb-make-sample failed" >&2; exit 1; }

# expect CODE ARGS...: runs pnb-inspect, keeps stdout/stderr in $dir/out and $dir/err.
expect() {
    want=$1
    shift
    "$inspect" "$@" >"$dir/out" 2>"$dir/err"
    got=$?
    if [ "$got" != "$want" ]; then
        echo "FAIL: pnb-inspect $* exited $got, expected $want" >&2
        cat "$dir/err" >&2
        status=1
    fi
}
# contains FILE TEXT
contains() {
    grep -qF -- "$2" "$dir/$1" || { echo "FAIL: $1 lacks '$2'" >&2; status=1; }
}

expect 0 --help
contains out "Exit codes:"
contains out "--no-checksums"
contains out "--strict"
expect 1
contains err "Error: no input file"
expect 1 --bogus "$sample"
contains err "Error: unknown option '--bogus'"
expect 1 "$sample" "$sample"
expect 2 "$dir/missing.pnb"
contains err "Error: io-error"
expect 0 "$sample"
contains out "tinted-glass"
expect 0 --verify "$sample"
contains out "verify: ok ("
expect 0 "$sample" --scan --no-checksums
contains out "scanning chunk headers"
expect 0 -- "$sample"

printf 'not a container\n' >"$dir/text.pnb"
expect 2 --verify "$dir/text.pnb"
contains err "Error: bad-magic at byte 0"

[ "$status" = 0 ] && echo "inspect_cli_test: ok"
exit $status
