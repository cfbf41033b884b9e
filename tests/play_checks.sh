#!/usr/bin/env bash
# End-to-end checks of `brume play`: split frame ranges reproduce a full run byte for byte, the
# video is encoded, an interrupted run leaves only complete frames, bad ranges are refused.
# Usage: play_checks.sh BRUME SCRATCH_DIR
set -u
brume=$1
scratch=$2
lavapipe=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
export VK_DRIVER_FILES=$lavapipe VK_ICD_FILENAMES=$lavapipe
mkdir -p "$scratch"
work=$(mktemp -d "$scratch/play_checks.XXXXXX")
cd "$work" || exit 2
passed=0
failed=0
ok() { echo "ok $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1: $2"; failed=$((failed + 1)); }

# --list names every shipped preset and marks the default.
if out=$("$brume" play --list 2>&1); then
    missing=""
    for p in plume ground-fog campfire explosion fog-bank crossing layers; do
        printf '%s\n' "$out" | grep -q "^$p " || missing="$missing $p"
    done
    if [ -n "$missing" ]; then fail list "missing:$missing"
    elif ! printf '%s\n' "$out" | grep -q "(default)"; then fail list "no default marked"
    else ok list; fi
else
    fail list "exit status $?"
fi

# Farm: frames 0-5 in one run equal frames 0-2 and 3-5 rendered by two separate runs.
small=(--size 64x48 --format png,exr)
"$brume" play crossing -o full --frames 0-5 "${small[@]}" >full.log 2>&1 || fail farm.full "exit $?: $(tail -1 full.log)"
"$brume" play crossing -o split --frames 3-5 "${small[@]}" >split2.log 2>&1 || fail farm.split "exit $?: $(tail -1 split2.log)"
"$brume" play crossing -o split --frames 0-2 "${small[@]}" >split1.log 2>&1 || fail farm.split "exit $?: $(tail -1 split1.log)"
diffs=""
for f in 0000 0001 0002 0003 0004 0005; do
    for ext in png exr; do
        cmp -s "full/crossing.$f.$ext" "split/crossing.$f.$ext" || diffs="$diffs crossing.$f.$ext"
    done
done
if [ -z "$diffs" ]; then ok farm.split_equals_full; else fail farm.split_equals_full "differ:$diffs"; fi
# The frames really change over time (a frozen simulation would pass the check above trivially).
if cmp -s full/crossing.0000.exr full/crossing.0005.exr; then fail farm.frames_move "frame 0 == frame 5"; else ok farm.frames_move; fi

# Video: an MP4 (ISO base media: 'ftyp' at byte 4) of the frames.
if command -v ffmpeg >/dev/null 2>&1; then
    if "$brume" play crossing -o vid --frames 0-5 --size 64x48 --video vid/crossing.mp4 >vid.log 2>&1 &&
        [ "$(head -c 8 vid/crossing.mp4 2>/dev/null | tail -c 4)" = "ftyp" ]; then
        ok video
    else
        fail video "$(tail -2 vid.log)"
    fi
else
    echo "skip video: ffmpeg not installed"
fi

# Interrupted: SIGINT after the first frame; exit 130, every written frame complete, no temp files.
"$brume" play plume -o intr --size 96x72 >intr.log 2>&1 &
pid=$!
for _ in $(seq 1 200); do
    [ -e intr/plume.0000.png ] && break
    sleep 0.05
done
kill -INT "$pid" 2>/dev/null
wait "$pid"
rc=$?
bad=""
for f in intr/*; do
    [ "$(head -c 4 "$f" | od -An -tx1 | tr -d ' \n')" = "89504e47" ] || bad="$bad $f"
done
hidden=$(ls -A intr | grep '^\.' || true)
if [ "$rc" -ne 130 ]; then fail interrupt "exit status $rc, expected 130"
elif [ -n "$bad" ] || [ -n "$hidden" ]; then fail interrupt "incomplete or temporary files:$bad $hidden"
elif ! grep -q "interrupted" intr.log; then fail interrupt "no message"
else ok interrupt; fi

# Bad requests are refused before any frame is written.
"$brume" play crossing -o bad --frames 5-2 >bad.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "frames" bad.log && [ ! -e bad/crossing.0005.png ]; then ok bad.range; else fail bad.range "rc $rc: $(tail -1 bad.log)"; fi
"$brume" play no-such-preset >bad2.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "plume" bad2.log; then ok bad.unknown_preset_lists_names; else fail bad.unknown_preset_lists_names "rc $rc: $(tail -1 bad2.log)"; fi

echo "$passed passed, $failed failed"
cd "$scratch" || exit 1
if [ "$failed" -ne 0 ]; then echo "outputs kept in $work"; exit 1; fi
rm -rf -- "$work"
exit 0
