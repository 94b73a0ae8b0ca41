#!/usr/bin/env bash
# Outputs (issue 14): every write is checked, close included; '-' is stdout where it makes sense;
# a reader that stops early ends a command quietly.  Usage: outputs.sh NESSHI SOURCE_DIR WORK_DIR
set -u
n=$1; src=$2; work=$3
mkdir -p "$work"
cd "$src" || exit 1
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# full CMD...: exit 1 and "nesshi CMD: error: writing 'PATH': No space left on device" (or
# "writing standard output: ..." when stdout is /dev/full).
full() {
    local what=$1; shift
    local out rc
    out=$("$@" 2>&1); rc=$?
    [ $rc -eq 1 ] || fail "$what: exit $rc, expected 1: $out"
    echo "$out" | grep -q "^nesshi[a-z ]*: error: writing \('/dev/full'\|standard output\): No space left on device$" ||
        fail "$what: message: $out"
    [ "$(echo "$out" | grep -c "error: writing")" -eq 1 ] || fail "$what: the error said more than once: $out"
}
words=tests/iss/programs/echo_input.txt
full "asm -o" $n asm examples/dot3.s -o /dev/full
full "asm --listing" $n asm examples/dot3.s -o "$work/dot3.o" --listing /dev/full
full "sim --fifo-out" $n sim examples/fifo_echo.s -q --fifo-in $words --fifo-out /dev/full
full "sim --trace" $n sim examples/dot3.s -q --trace /dev/full
full "sim --trace chrome" $n sim examples/dot3.s -q --trace /dev/full --trace-format chrome
full "sim --stats-json" $n sim examples/dot3.s -q --stats-json /dev/full
full "render -o" $n render tetra:1 --size 8 --grid 4 -q -o /dev/full
full "render --id-buffer" $n render tetra:1 --size 8 --grid 4 -q --id-buffer /dev/full
full "render --t-buffer" $n render tetra:1 --size 8 --grid 4 -q --t-buffer /dev/full
full "render --stats-json" $n render tetra:1 --size 8 --grid 4 -q --stats-json /dev/full
full "scene gen -o" $n scene gen balls -s 1 -o /dev/full
full "kernels --json" $n kernels --json /dev/full
full "loop --json" $n loop examples/saxpy_pipelined.s --json /dev/full
# schedule -o replaces a regular file through FILE.tmp and a rename; a device or a pipe is written
# to, never renamed over (as root that rename replaced /dev/full with a plain file). Checked on a
# named pipe of our own, so a regression cannot break the machine's /dev/full.
rm -f "$work/sched.pipe" && mkfifo "$work/sched.pipe"
timeout 20 cat "$work/sched.pipe" >"$work/sched.out" &
timeout 20 $n schedule -m os tests/cli/schedule/normalize.pk -o "$work/sched.pipe" || fail "schedule -o PIPE: exit $?"
wait
[ -p "$work/sched.pipe" ] || fail "schedule -o PIPE renamed a plain file over the pipe"
grep -q "{" "$work/sched.out" || fail "schedule -o PIPE: nothing came through the pipe"
full "pipeline -o" $n pipeline examples/linear/saxpy.sa -o /dev/full
# stdout on /dev/full: short outputs too (they fail only at the flush at exit).
for cmd in "isa" "kernels" "isa --machine-toml os" "scene gen balls -s 1" "render tetra:1 --size 8 --grid 4" \
           "sim examples/dot3.s" "asm examples/dot3.s -o -" "loop examples/saxpy_pipelined.s" "--version"; do
    full "$cmd > /dev/full" sh -c "exec $n $cmd > /dev/full"
done
full "dis > /dev/full" sh -c "$n asm examples/dot3.s -o '$work/dot3.o' && exec $n dis '$work/dot3.o' > /dev/full"
[ -c /dev/full ] || fail "/dev/full is no longer a device"

# A reader that stops early: no message, no signal death, exit 0 (one rule, whether the output
# fitted in the pipe before head left or a write failed). `| head -n 0` after a pause: the reader
# is surely gone, so the write fails: still exit 0, quietly.
quiet_pipe() {
    local what=$1; shift
    local rc
    rc=$("$@" 2>"$work/pipe.err" | head -1 >/dev/null; echo "${PIPESTATUS[0]}")
    [ "$rc" -eq 0 ] || fail "$what | head -1: exit $rc, expected 0"
    [ ! -s "$work/pipe.err" ] || fail "$what | head -1: printed $(cat "$work/pipe.err")"
    rc=$(sh -c "sleep 0.3; exec \"\$@\"" sh "$@" 2>"$work/pipe.err" | head -n 0; echo "${PIPESTATUS[0]}")
    [ "$rc" -eq 0 ] || fail "$what | head -n 0: exit $rc, expected 0"
    [ ! -s "$work/pipe.err" ] || fail "$what | head -n 0: printed $(cat "$work/pipe.err")"
}
quiet_pipe "isa" $n isa
quiet_pipe "kernels" $n kernels
quiet_pipe "render" $n render tetra:1 --size 8 --grid 4
quiet_pipe "render -o -" $n render tetra:1 --size 8 --grid 4 -q -o -
quiet_pipe "dis" $n dis "$work/dot3.o"
# Progress is on stderr: the paper's summary is what a pipe sees.
out=$($n paper --size 8 --scenes tetra:1 --grids 4 --models V --out "$work/paper" 2>/dev/null)
echo "$out" | grep -q "^cells: " || fail "paper stdout: $out"
echo "$out" | grep -q "tetra:1" && fail "paper prints progress on stdout: $out"

# '-' is stdout where it makes sense.
$n asm examples/dot3.s -o - >"$work/stdout.o" && $n asm examples/dot3.s -o "$work/file.o" &&
    cmp -s "$work/stdout.o" "$work/file.o" || fail "asm -o - differs from asm -o FILE"
$n render tetra:1 --size 8 --grid 4 -o - 2>"$work/report.txt" | head -c 8 | od -c | grep -q "P   N   G" ||
    fail "render -o - is not a PNG on stdout"
grep -q "model native" "$work/report.txt" || fail "render -o -: the report is not on stderr"
$n render tetra:1 --size 8 --grid 4 -q --id-buffer - >"$work/stdout.id" &&
    $n render tetra:1 --size 8 --grid 4 -q --id-buffer "$work/file.id" && cmp -s "$work/stdout.id" "$work/file.id" ||
    fail "render --id-buffer - differs"
$n kernels --json - 2>/dev/null | head -c 1 | grep -q "{" || fail "kernels --json - is not JSON on stdout"
$n sim examples/dot3.s --stats-json - 2>/dev/null | head -c 1 | grep -q "{" || fail "sim --stats-json -"
$n sim examples/fifo_echo.s -q --fifo-in $words --fifo-out - | grep -q "^0x0000000b  # 11" || fail "sim --fifo-out -"
$n schedule -m os tests/cli/schedule/normalize.pk -o - | grep -q "{" || fail "schedule -o -"
$n scene gen balls -s 1 -o - | grep -q "^s 0 0 0 0.5" || fail "scene gen -o -"

# refused: two outputs on stdout, and outputs that have no stdout form
refused() {
    local what=$1 pattern=$2; shift 2
    local out rc
    out=$("$@" 2>&1); rc=$?
    [ $rc -eq 2 ] || fail "$what: exit $rc, expected 2: $out"
    echo "$out" | grep -q -- "$pattern" || fail "$what: message: $out"
}
refused "render two stdouts" "error: -o - and --id-buffer - would both write to standard output" \
    $n render tetra:1 --size 8 --grid 4 -o - --id-buffer -
refused "asm two stdouts" "error: -o - and --listing - would both" $n asm examples/dot3.s -o - --listing -
refused "sim dump and stdout" "error: --dump prints on stdout" $n sim examples/saxpy_pipelined.s --stats-json - --dump ys
refused "demo -o -" "error: -o cannot be '-' (standard output)" $n demo -o -
refused "paper --out -" "error: --out cannot be '-' (standard output): it is a folder" $n paper --out -
refused "pipeline --sequential -" "error: --sequential cannot be '-'" $n pipeline examples/linear/saxpy.sa --sequential -

[ $fails -eq 0 ] || { echo "$fails failures"; exit 1; }
echo "outputs: all checks passed"
