#!/usr/bin/env bash
# End-to-end checks of `brume preview` with a real window (ctest runs this under xvfb-run): its
# screenshots are the frames `brume play` writes, byte for byte, for three presets and two methods;
# scrubbing backwards equals playing forwards; a scripted orbit puts the camera where the closed form
# does and renders what `brume render` renders from there; the validation layer stays silent across
# resizes and method switches; Save adds a missing key to its table; an edit the simulator does not
# read keeps the checkpoints; "render sequence" writes brume play's frames byte for byte; brume bench
# preview prints its table; a slow frame does not stop the window presenting; bad scripts and a
# missing display are refused in one clear line.
# Usage: preview_checks.sh BRUME SCRATCH_DIR
set -u
brume=$(realpath "$1")
scratch=$2
data=$(cd "$(dirname "$0")/data" && pwd)
presets=$(cd "$(dirname "$0")/../presets" && pwd)
lavapipe=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
export VK_DRIVER_FILES=$lavapipe VK_ICD_FILENAMES=$lavapipe
mkdir -p "$scratch"
work=$(mktemp -d "$scratch/preview_checks.XXXXXX")
cd "$work" || exit 2
passed=0
failed=0
ok() { echo "ok $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1: $2"; failed=$((failed + 1)); }
# Width and height from a PNG's IHDR chunk.
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{printf "%dx%d", $3 * 256 + $4, $7 * 256 + $8}'; }

if [ -z "${DISPLAY:-}" ]; then echo "FAIL setup: no DISPLAY (run under xvfb-run, as ctest does)"; exit 1; fi

# No display: one line naming the problem, non-zero exit, no window attempted.
env -u DISPLAY -u WAYLAND_DISPLAY "$brume" preview plume >nodisplay.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && [ "$(wc -l <nodisplay.log)" -eq 1 ] && grep -q "no X11 display: set DISPLAY" nodisplay.log; then
    ok no_display_refused
else
    fail no_display_refused "rc $rc: $(cat nodisplay.log)"
fi
# WAYLAND_DISPLAY alone is no display for Debian's GLFW (its X11 build): refused the same way, not
# with GLFW's "X11: The DISPLAY environment variable is missing".
env -u DISPLAY WAYLAND_DISPLAY=wayland-9 "$brume" preview plume >wayland.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && [ "$(wc -l <wayland.log)" -eq 1 ] && grep -q "no X11 display: set DISPLAY" wayland.log; then
    ok wayland_alone_refused
else
    fail wayland_alone_refused "rc $rc: $(head -c 300 wayland.log)"
fi

# A bad script line is refused as FILE:LINE before any window opens.
printf 'frame 2\n# a comment\nwait 0\n' >bad.script
"$brume" preview plume --script bad.script >badscript.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "bad.script:3: the number of frames must be at least 1" badscript.log; then
    ok bad_script_line
else
    fail bad_script_line "rc $rc: $(cat badscript.log)"
fi
printf 'wait 1\nmethod nosuch\nquit\n' >badmethod.script
"$brume" preview plume --size 64x48 --script badmethod.script >badmethod.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "badmethod.script:2: unknown method 'nosuch'" badmethod.log; then
    ok bad_script_method
else
    fail bad_script_method "rc $rc: $(cat badmethod.log)"
fi

# Screenshots equal `brume play` byte for byte: three presets, two methods, a frame past the first.
frame=5
size=96x72
for preset in plume campfire crossing; do
    for method in ppll soft; do
        tag=$preset.$method
        "$brume" play "$preset" -o "play.$tag" --frames $frame-$frame --size $size --method $method --format png \
            >"play.$tag.log" 2>&1 || { fail "screenshot.$tag" "play failed: $(tail -1 "play.$tag.log")"; continue; }
        "$brume" preview "$preset" --size $size --method $method --frame $frame --screenshot "shot.$tag.png" \
            --validate >"shot.$tag.log" 2>&1
        rc=$?
        want=$(printf 'play.%s/%s.%04d.png' "$tag" "$preset" $frame)
        if [ "$rc" -ne 0 ]; then fail "screenshot.$tag" "rc $rc: $(tail -1 "shot.$tag.log")"
        elif ! cmp -s "shot.$tag.png" "$want"; then fail "screenshot.$tag" "differs from $want"
        else ok "screenshot.$tag"; fi
    done
done
# The frames differ between methods and presets, so the comparisons above can fail.
if [ ! -s shot.plume.ppll.png ] || [ ! -s shot.plume.soft.png ] || [ ! -s shot.crossing.ppll.png ]; then
    fail screenshots_differ "screenshots missing"
elif cmp -s shot.plume.ppll.png shot.plume.soft.png || cmp -s shot.plume.ppll.png shot.crossing.ppll.png; then
    fail screenshots_differ "two different renders gave the same file"
else
    ok screenshots_differ
fi

# Scrubbing backwards (past two checkpoints) and playing forwards both reach frame 6 as play renders it.
"$brume" play crossing -o play.scrub --frames 6-6 --size 80x60 --format png >play.scrub.log 2>&1
printf 'frame 20\nwait 1\nscreenshot f20.png\nframe 6\nwait 1\nscreenshot back.png\nframe 0\nwait 1\nplay\nwait 6\npause\nscreenshot forward.png\nquit\n' \
    >scrub.script
"$brume" preview crossing --size 80x60 --script scrub.script --validate >scrub.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then fail scrub "rc $rc: $(tail -1 scrub.log)"
elif ! cmp -s back.png play.scrub/crossing.0006.png; then fail scrub.backwards "frame 6 after scrubbing back differs from play"
elif ! cmp -s forward.png play.scrub/crossing.0006.png; then fail scrub.forwards "frame 6 after playing 6 frames differs from play"
elif cmp -s f20.png back.png; then fail scrub.frames_move "frame 20 looks like frame 6"
else ok scrub_backwards_equals_forwards; fi

# Orbit: the camera lands where the closed form puts it (spherical coordinates about look_at, not the
# preview's rotation formula), and the screenshot equals brume render of a scene with that camera.
printf 'wait 1\norbit 30 15\ncamera\nscreenshot orbit.png\nquit\n' >orbit.script
"$brume" preview "$data/small.toml" --size 64x48 --script orbit.script --validate >orbit.log 2>&1
rc=$?
cam=$(grep '^camera position' orbit.log)
if [ "$rc" -ne 0 ] || [ -z "$cam" ]; then
    fail orbit "rc $rc: $(tail -1 orbit.log)"
else
    # small.toml: eye (0, 0.5, 5), look_at (0, 0.3, 0), up +y.
    verdict=$(echo "$cam" | awk '{
        pi = atan2(0, -1); dx = 0; dy = 0.2; dz = 5; L = sqrt(dx*dx + dy*dy + dz*dz)
        az = atan2(dx, dz) + 30 * pi / 180; el = atan2(dy, sqrt(dx*dx + dz*dz)) + 15 * pi / 180
        ex = L * cos(el) * sin(az); ey = 0.3 + L * sin(el); ez = L * cos(el) * cos(az)
        err = sqrt(($3 - ex)^2 + ($4 - ey)^2 + ($5 - ez)^2)
        if (err < 1e-9 && $7 == 0 && $8 == 0.3 && $9 == 0) print "ok"; else printf "off by %g: got %s %s %s, want %.12g %.12g %.12g", err, $3, $4, $5, ex, ey, ez }')
    if [ "$verdict" != "ok" ]; then
        fail orbit.closed_form "$verdict"
    else
        ok orbit.closed_form
        read -r _ _ px py pz _ <<<"$cam"
        sed "s/^position = .*/position = [$px, $py, $pz]/" "$data/small.toml" >orbited.toml
        "$brume" render orbited.toml --png rendered.png >render.log 2>&1
        if cmp -s orbit.png rendered.png; then ok orbit.equals_render
        else fail orbit.equals_render "differs from brume render of the orbited camera: $(tail -1 render.log)"; fi
        "$brume" render "$data/small.toml" --png unorbited.png >unorbited.log 2>&1
        if cmp -s orbit.png unorbited.png; then fail orbit.moves "the orbited view equals the unorbited one"
        else ok orbit.moves; fi
    fi
fi

# Error against the reference, on a worker thread: the exact method matches it to float precision
# (1e-4 of the peak, docs/accuracy.md), an approximate one does not. crossing: its shadows are
# per-sphere, for which the exact methods are exact (the accurate technique has its own stated error).
printf 'frame 10\nwait 1\nreference-error\nmethod wsum\nwait 1\nreference-error\nquit\n' >reference.script
"$brume" preview crossing --size 128x96 --script reference.script --validate >reference.log 2>&1
rc=$?
verdict=$(grep '^reference error:' reference.log | awk '{ for (i = 1; i <= NF; i++) if ($i == "max") v[NR] = $(i + 1) }
    END { if (NR == 2 && v[1] < 1e-4 && v[2] > 1e-2) print "ok"; else printf "%d lines, auto %s, wsum %s", NR, v[1], v[2] }')
if [ "$rc" -ne 0 ]; then fail reference_error "rc $rc: $(tail -1 reference.log)"
elif [ "$verdict" != ok ]; then fail reference_error "$verdict"
elif ! grep -q "method auto at 128x96" reference.log; then fail reference_error "not at the viewport's size: $(grep '^reference' reference.log | head -1)"
else ok reference_error_exact_vs_approximate; fi

# Validation stays clean across resizes (the swapchain is recreated) and method switches, and the
# screenshot follows the new size.
printf 'wait 2\nresize 120 90\nwait 2\nmethod soft\nwait 2\nmethod kbuf:4\nresize 80 60\nwait 2\nscreenshot resized.png\nquit\n' \
    >resize.script
"$brume" preview plume --size 96x72 --script resize.script --validate >resize.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then fail resize "rc $rc: $(tail -3 resize.log)"
elif [ "$(png_size resized.png)" != "80x60" ]; then fail resize "screenshot is $(png_size resized.png), want 80x60"
else ok resize_and_method_switch_validation_clean; fi

# The scripted run's benchmark line: frames shown and the time of each part.
if grep -q "^preview: [0-9]* frames shown; the last [0-9]* at internal resolution [0-9]*x[0-9]* of 80x60: [0-9.]* FPS, mean ms per frame: simulate" resize.log; then ok benchmark_line
else fail benchmark_line "no summary in resize.log"; fi

# Live edits: `set` of the emitter's rate changes the frame, and equals brume play of the file edited
# the same way; a value the reader refuses is named with its key.
sed 's/^rate = 220.0$/rate = 600.0/' "$presets/plume.toml" >plume-edited.toml
"$brume" play plume-edited.toml -o play.edited --frames 12-12 --size 96x72 --format png >play.edited.log 2>&1
printf 'frame 12\nwait 1\nscreenshot unedited.png\nset emitter[0].rate 600.0\nwait 1\nscreenshot edited.png\nquit\n' >set.script
"$brume" preview plume --size 96x72 --script set.script --validate >set.log 2>&1
rc=$?
played=$(ls play.edited/*.0012.png 2>/dev/null | head -1)
if [ "$rc" -ne 0 ]; then fail set "rc $rc: $(tail -1 set.log)"
elif ! grep -q '^rate = 600.0$' plume-edited.toml; then fail set "the sed edit did not apply to plume.toml"
elif cmp -s unedited.png edited.png; then fail set.changes "the rate did not change the frame"
elif [ -z "$played" ] || ! cmp -s edited.png "$played"; then fail set.equals_play "differs from play of the edited file"
else ok set_equals_play_of_edited_file; fi
# Save: the edited preset written where its values stand (only the edited line changes, comments
# stay), and brume play of the saved file renders the frame the preview showed.
printf 'frame 12\nset emitter[0].rate 600.0\nwait 1\nscreenshot before-save.png\nsave saved.toml\nquit\n' >save.script
"$brume" preview plume --size 96x72 --script save.script --validate >save.log 2>&1
rc=$?
"$brume" play saved.toml -o play.saved --frames 12-12 --size 96x72 --format png >play.saved.log 2>&1
saved_png=$(ls play.saved/*.0012.png 2>/dev/null | head -1)
changed=$(diff "$presets/plume.toml" saved.toml 2>/dev/null | grep -c '^[<>]')
if [ "$rc" -ne 0 ]; then fail save "rc $rc: $(tail -1 save.log)"
elif [ "$changed" != 2 ] || ! grep -q '^rate = 600.0$' saved.toml; then fail save.in_place "$changed changed lines: $(diff "$presets/plume.toml" saved.toml | head -5)"
elif [ -z "$saved_png" ] || ! cmp -s before-save.png "$saved_png"; then fail save.plays_back "play of the saved file differs"
else ok save_keeps_comments_and_plays_back; fi

printf 'set emitter[0].rate -5\nquit\n' >setbad.script
"$brume" preview plume --size 64x48 --script setbad.script >setbad.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "setbad.script:1: emitter\[0\].rate: must not be negative" setbad.log; then ok set_refused_names_key
else fail set_refused_names_key "rc $rc: $(tail -1 setbad.log)"; fi

# Save of a key the file leaves out (a default): the line is added to its table, every other line
# stays, and brume play of the saved file renders the frame the preview showed.
printf 'frame 12\nset emitter[0].stop 6.2\nwait 1\nscreenshot stop-preview.png\nsave saved-stop.toml\nquit\n' >savenew.script
"$brume" preview plume --size 96x72 --script savenew.script --validate >savenew.log 2>&1
rc=$?
"$brume" play saved-stop.toml -o play.stop --frames 12-12 --size 96x72 --format png >play.stop.log 2>&1
stop_png=$(ls play.stop/*.0012.png 2>/dev/null | head -1)
added=$(diff "$presets/plume.toml" saved-stop.toml 2>/dev/null | grep -c '^>')
removed=$(diff "$presets/plume.toml" saved-stop.toml 2>/dev/null | grep -c '^<')
if [ "$rc" -ne 0 ]; then fail save_new_key "rc $rc: $(tail -1 savenew.log)"
elif [ "$added" != 1 ] || [ "$removed" != 0 ] || ! grep -q '^stop = 6.2$' saved-stop.toml; then
    fail save_new_key.added_line "+$added -$removed lines: $(diff "$presets/plume.toml" saved-stop.toml | head -5)"
elif [ "$(awk '/^stop = 6.2$/ { print prev } { if ($0 ~ /^\[/) prev = $0 }' saved-stop.toml)" != "[[emitter]]" ]; then
    fail save_new_key.table "the line is not in the [[emitter]] table"
elif [ -z "$stop_png" ] || ! cmp -s stop-preview.png "$stop_png"; then fail save_new_key.plays_back "play of the saved file differs"
elif cmp -s stop-preview.png unedited.png; then fail save_new_key.changes "the edit did not change the frame"
else ok save_new_key_in_its_table_and_plays_back; fi

# An edit the simulator does not read (the light) keeps the simulated frames and checkpoints, and the
# frame still equals brume play of the file edited the same way.
sed 's/^sun = \[1.6, 1.4, 1.15\]$/sun = [3.0, 0.5, 0.5]/' "$presets/plume.toml" >plume-sun.toml
"$brume" play plume-sun.toml -o play.sun --frames 20-20 --size 96x72 --format png >play.sun.log 2>&1
printf 'frame 20\nwait 1\nset lighting.sun [3.0, 0.5, 0.5]\nwait 1\nscreenshot sun.png\nset emitter[0].rate 300.0\nquit\n' >keep.script
"$brume" preview plume --size 96x72 --script keep.script --validate >keep.log 2>&1
rc=$?
sun_png=$(ls play.sun/*.0020.png 2>/dev/null | head -1)
if [ "$rc" -ne 0 ]; then fail edit_keeps_simulation "rc $rc: $(tail -1 keep.log)"
elif ! grep -q '^sun = \[3.0, 0.5, 0.5\]$' plume-sun.toml; then fail edit_keeps_simulation "the sed edit did not apply"
elif ! grep -q "^set lighting.sun = \[3.0, 0.5, 0.5\] (simulated frames kept: 0-20, 3 checkpoints)" keep.log; then
    fail edit_keeps_simulation.kept "$(grep '^set' keep.log)"
elif ! grep -q "^set emitter\[0\].rate = 300.0 (the simulation restarts from frame 0)" keep.log; then
    fail edit_keeps_simulation.restarts "$(grep '^set' keep.log)"
elif [ -z "$sun_png" ] || ! cmp -s sun.png "$sun_png"; then fail edit_keeps_simulation.equals_play "differs from play of the edited file"
else ok edit_keeps_simulation_it_does_not_change; fi

# An edit of a preset with a density grid is prepared (the grid converted again) on a worker while
# the window keeps running; once it is shown, the frame equals brume play of the file edited the same way.
sed 's/^extinction_scale = 3.0$/extinction_scale = 1.5/' "$presets/vdb-cloud.toml" >vdb-edited.toml
"$brume" play vdb-edited.toml -o play.vdb --frames 4-4 --size 64x48 --format png >play.vdb.log 2>&1
printf 'frame 4\nwait 1\nscreenshot vdb-before.png\nset vdb[0].extinction_scale 1.5\nwait 1\nscreenshot vdb-after.png\nquit\n' >vdb.script
"$brume" preview vdb-cloud --size 64x48 --script vdb.script --validate >vdb.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then fail edit_on_worker "rc $rc: $(tail -1 vdb.log)"
elif ! grep -q '^extinction_scale = 1.5$' vdb-edited.toml; then fail edit_on_worker "the sed edit did not apply"
elif ! grep -q '^set vdb\[0\].extinction_scale = 1.5 (preparing on a worker)$' vdb.log; then fail edit_on_worker.worker "$(grep '^set' vdb.log)"
elif cmp -s vdb-before.png vdb-after.png; then fail edit_on_worker.changes "the edit did not change the frame"
elif ! cmp -s vdb-after.png play.vdb/vdb-cloud.0004.png; then fail edit_on_worker.equals_play "differs from play of the edited file"
else ok edit_prepared_on_worker_equals_play; fi

# Render sequence: brume play in the background, with the view's method and size and the edited
# preset; byte for byte what brume play writes with the same options.
printf 'wait 1\nmethod soft\nset emitter[0].rate 600.0\nrender-sequence seq 3-5\nwait 1\nquit\n' >sequence.script
"$brume" preview plume --size 64x48 --script sequence.script --validate >sequence.log 2>&1
rc=$?
"$brume" play plume-edited.toml -o play.seq --frames 3-5 --size 64x48 --method soft --format png >play.seq.log 2>&1
same=0
for f in 3 4 5; do
    name=$(printf 'plume.%04d.png' $f)
    cmp -s "seq/$name" "play.seq/$name" && same=$((same + 1))
done
if [ "$rc" -ne 0 ]; then fail render_sequence "rc $rc: $(tail -2 sequence.log)"
elif ! grep -q "^render-sequence: 3 of 3 frames written by brume play: wrote 3 frames" sequence.log; then
    fail render_sequence.progress "$(grep render-sequence sequence.log)"
elif [ "$same" != 3 ]; then fail render_sequence.equals_play "$same of 3 frames equal brume play's"
elif cmp -s seq/plume.0003.png seq/plume.0004.png; then fail render_sequence.frames_move "frames 3 and 4 are the same"
else ok render_sequence_equals_play; fi

# The same from a file without [preset] name (the name is its stem), edited: the frames are named
# as brume play names them for that file, and equal them.
grep -v '^name = "plume"$' "$presets/plume.toml" >myplume.toml
mkdir -p edited && sed 's/^rate = 220.0$/rate = 600.0/' myplume.toml >edited/myplume.toml
printf 'wait 1\nset emitter[0].rate 600.0\nrender-sequence seq2 2-3\nquit\n' >sequence2.script
"$brume" preview myplume.toml --size 64x48 --script sequence2.script --validate >sequence2.log 2>&1
rc=$?
"$brume" play edited/myplume.toml -o play.seq2 --frames 2-3 --size 64x48 --format png >play.seq2.log 2>&1
if [ "$rc" -ne 0 ]; then fail render_sequence.stem_name "rc $rc: $(tail -2 sequence2.log)"
elif grep -q '^name = "plume"$' myplume.toml || ! grep -q '^rate = 600.0$' edited/myplume.toml; then fail render_sequence.stem_name "the edits of the test files did not apply"
elif ! cmp -s seq2/myplume.0002.png play.seq2/myplume.0002.png || ! cmp -s seq2/myplume.0003.png play.seq2/myplume.0003.png; then
    fail render_sequence.stem_name "frames differ or are misnamed: $(ls seq2 | tr '\n' ' ')"
elif ls -a | grep -q 'preview-sequence'; then fail render_sequence.stem_name "the hidden copy of the preset was left behind"
else ok render_sequence_named_by_stem; fi

# brume bench preview: a window per preset, the figures side by side; with no display, one line.
env -u DISPLAY -u WAYLAND_DISPLAY "$brume" bench preview >bench-nodisplay.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && [ "$(wc -l <bench-nodisplay.log)" -eq 1 ] && grep -q "bench preview opens a window: no X11 display" bench-nodisplay.log; then
    ok bench_preview_no_display_refused
else
    fail bench_preview_no_display_refused "rc $rc: $(cat bench-nodisplay.log)"
fi
"$brume" bench preview --presets campfire,crossing --preview-frames 3 --frames 1 --size 64x48 --validate >bench.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then fail bench_preview "rc $rc: $(tail -2 bench.log)"
elif [ "$(grep -cE '^(campfire|crossing) +[0-9]+x[0-9]+ +[0-9.]+ ' bench.log)" != 2 ]; then fail bench_preview "no table rows: $(tail -4 bench.log)"
else ok bench_preview_table; fi

# A slow frame does not hold the window: the test hook BRUME_PREVIEW_SLOW_FRAME_MS makes the render
# thread take 1.2 s over each view, and the main loop must go on presenting (at 10 Hz at least with no
# input) and polling events meanwhile; a loop that rendered its frames itself would do neither for
# 1.2 s. The scripted screenshot still waits for the frame the script set: play's frame, byte for byte.
printf 'frame %d\nwait 1\nscreenshot slow.png\nquit\n' $frame >slow.script
BRUME_PREVIEW_SLOW_FRAME_MS=1200 "$brume" preview plume --size $size --method ppll --script slow.script --validate \
    >slow.log 2>&1
rc=$?
line=$(grep '^preview: the window presented' slow.log)
field() { echo "$line" | sed -n "s/$1/\1/p"; }
verdict=$(echo "$(field '.*; \([0-9]*\) frames rendered.*') $(field '.* times, \([0-9]*\) of them.*') \
    $(field '.*between two presents \([0-9.]*\) ms.*') $(field '.*at most \([0-9.]*\) ms apart.*')" | awk '{
    if ($1 >= 2 && $2 >= 10 && $3 < 600 && $4 < 300) print "ok"
    else printf "%s frames rendered, %s presents while rendering, presents %s ms and polls %s ms apart at most", $1, $2, $3, $4 }')
if [ "$rc" -ne 0 ] || [ -z "$line" ]; then fail slow_frame "rc $rc: $(tail -2 slow.log)"
elif [ "$verdict" != "ok" ]; then fail slow_frame.window_presents "$verdict: $line"
elif ! cmp -s slow.png "play.plume.ppll/plume.$(printf %04d $frame).png"; then fail slow_frame.screenshot "differs from play"
else ok slow_frame_does_not_block_the_window; fi

# Hot reload: a broken file is refused with its file:line error while the last good frame stays; the
# fixed file is read and shown. The shell edits the file while the preview's script waits for it.
wait_for() {  # wait_for FILE PATTERN [N]: up to 60 s for N (default 1) lines matching in FILE
    for _ in $(seq 1 600); do
        [ "$(grep -c "$2" "$1" 2>/dev/null)" -ge "${3:-1}" ] && return 0
        sleep 0.1
    done
    return 1
}
cp "$data/small.toml" live.toml
printf 'wait 1\nscreenshot good.png\nwait-reload\nwait 1\nscreenshot broken.png\nwait-reload\nwait 1\nscreenshot fixed.png\nquit\n' \
    >reload.script
"$brume" preview live.toml --size 64x48 --script reload.script --validate >reload.log 2>&1 &
reload_pid=$!
if wait_for reload.log "waiting for live.toml to change"; then
    printf '\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0\nextinction = 1.0\n' >>live.toml
    # The preview waits again only after it refused the broken file: then the fix is a change it sees.
    if wait_for reload.log "reload refused" && wait_for reload.log "waiting for live.toml to change" 2; then
        sed 's/extinction = 2.0/extinction = 6.0/' "$data/small.toml" >live.toml.new && mv live.toml.new live.toml
    fi
fi
wait "$reload_pid"
rc=$?
sed 's/extinction = 2.0/extinction = 6.0/' "$data/small.toml" >edited.toml
"$brume" render edited.toml --png edited.png >edited.log 2>&1
if [ "$rc" -ne 0 ]; then fail hot_reload "rc $rc: $(tail -2 reload.log)"
elif ! grep -q "reload refused, still playing the last good version: live.toml:[0-9]*:" reload.log; then
    fail hot_reload.error "no file:line error: $(grep -i reload reload.log)"
elif ! cmp -s good.png broken.png; then fail hot_reload.keeps_last_good "the broken file changed the frame"
elif cmp -s good.png fixed.png; then fail hot_reload.recovers "the fixed file was not shown"
elif ! cmp -s fixed.png edited.png; then fail hot_reload.recovers "the reloaded frame differs from brume render of the file"
else ok hot_reload; fi

# Save after a reload the preview refused: the file holds the user's newer text, which the preview's
# edits (made to the text it read) would overwrite with the old one. Refused, and the file stays as the
# user left it.
cp "$data/small.toml" keep.toml
printf 'set lighting.sun [3.0, 0.5, 0.5]\nwait-reload\nsave keep.toml\nquit\n' >keep.script
"$brume" preview keep.toml --size 64x48 --script keep.script >keep.log 2>&1 &
keep_pid=$!
wait_for keep.log "waiting for keep.toml to change" &&
    printf '\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0  # my work in progress\nextinction = 1.0\n' >>keep.toml
wait "$keep_pid"
rc=$?
{ cat "$data/small.toml"; printf '\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = -1.0  # my work in progress\nextinction = 1.0\n'; } >keep.expected
if [ "$rc" -eq 0 ]; then fail save_after_refused_reload "exit 0: $(tail -2 keep.log)"
elif ! grep -q "keep.script:3: save: keep.toml changed on disk since the preview read it" keep.log; then
    fail save_after_refused_reload "no such error: $(grep -i 'error' keep.log | head -2)"
elif ! cmp -s keep.toml keep.expected; then fail save_after_refused_reload "the file changed: $(diff keep.expected keep.toml | head -3)"
else ok save_after_refused_reload; fi

# SIGTERM (as Ctrl-C, or a closed terminal) closes the preview as Esc does: the sequence's brume play is
# stopped, the hidden copy of the edited preset goes, and the exit status is 130. The preview used to die
# at once, leaving play running to the end and the copy in the user's folder.
cp "$presets/plume.toml" sig.toml
printf 'set emitter[0].rate 600.0\nrender-sequence seqsig 0-143\nquit\n' >sig.script
"$brume" preview sig.toml --size 160x120 --script sig.script >sig.log 2>&1 &
sig_pid=$!
wait_for sig.log "^render-sequence .*seqsig: frames 0-143 started" && kill -TERM "$sig_pid"
wait "$sig_pid"
rc=$?
if [ "$rc" -ne 130 ]; then fail signal_closes_like_esc "rc $rc: $(tail -2 sig.log)"
elif ls -A | grep -q 'sig.preview-sequence'; then fail signal_closes_like_esc "the hidden copy of the preset was left behind"
elif for f in /proc/[0-9]*/cmdline; do tr '\0' ' ' <"$f" 2>/dev/null; echo; done | grep -q -- "--output seqsi[g]"; then
    fail signal_closes_like_esc "brume play is still running"  # (no pgrep: procps is not in every Debian image)
elif ! grep -q "preview interrupted by a signal" sig.log; then fail signal_closes_like_esc "no line says so: $(tail -1 sig.log)"
else ok signal_closes_like_esc; fi

# While a script waits for something other than frames (here a sequence brume play renders), the view
# is not rendered again and again: it was, 58 identical frames beside a 48-frame sequence.
line=$(grep '^preview: the window presented' sequence.log)
rendered=$(echo "$line" | sed -n 's/.*; \([0-9]*\) frames rendered.*/\1/p')
shown=$(sed -n 's/^preview: \([0-9]*\) frames shown.*/\1/p' sequence.log)
if [ -n "$rendered" ] && [ -n "$shown" ] && [ "$rendered" -le $((shown + 2)) ]; then ok render_sequence_renders_the_view_once
else fail render_sequence_renders_the_view_once "$rendered frames rendered for $shown shown"; fi

# A script that is a folder is refused by name (an ifstream opened it, and the window stayed open with
# no script); an editor's byte-order mark before the first command is no unknown command.
"$brume" preview plume --size 64x48 --script . >scriptdir.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "the script .: cannot read: is a directory" scriptdir.log; then ok script_folder_refused
else fail script_folder_refused "rc $rc: $(head -c 300 scriptdir.log)"; fi
printf '\xef\xbb\xbfframe 3\nquit\n' >bom.script
"$brume" preview plume --size 64x48 --script bom.script >bom.log 2>&1
rc=$?
if [ "$rc" -eq 0 ]; then ok script_byte_order_mark; else fail script_byte_order_mark "rc $rc: $(head -c 300 bom.log)"; fi

# A bad command line exits 2, as it does for render and play (these exited 1): a screenshot's name, a
# method setting, a CPU method, a frame outside the preset. No window opens for them.
bad_usage=0
for args in "--frame 1 --screenshot shot.gif" "--method kbuf:0" "--method reference" "--frame 99999" "--screenshot s.png"; do
    # shellcheck disable=SC2086
    timeout 60 "$brume" preview plume $args >usage.log 2>&1
    rc=$?
    if [ "$rc" -ne 2 ] || [ "$(grep -c '^brume: error: ' usage.log)" -ne 1 ]; then
        fail "usage.status_2" "preview $args: rc $rc: $(tail -1 usage.log)"
        bad_usage=1
    fi
done
[ "$bad_usage" -eq 0 ] && ok usage.status_2
# "-" (standard input for render and play) is refused by name: the preview watches and saves a file.
timeout 60 "$brume" preview - </dev/null >usage.log 2>&1
rc=$?
if [ "$rc" -eq 2 ] && [ "$(cat usage.log)" = "brume: error: preview - : the preview watches, reloads and saves its preset, so it needs a file, not standard input (save it to a file and open that)" ]; then
    ok usage.stdin_refused
else
    fail usage.stdin_refused "rc $rc: $(head -c 300 usage.log)"
fi

# A viewport too large for the device's memory: the line render gives, at most followed by the call's
# name, never a source path (the preview's render thread passes its failures on as text, which once
# showed the raw vkBindImageMemory call and its source line), and no screenshot. lavapipe refuses the
# 4 GiB target at once, without touching that memory.
timeout 120 "$brume" preview --size 16384x16384 --frame 3 --screenshot huge.png >huge.log 2>&1
rc=$?
advice="brume: error: the Vulkan device has too little memory for this frame's images and lists: try a smaller --size or a smaller scene"
if [ "$rc" -ne 1 ]; then fail memory.viewport_too_large "rc $rc: $(tail -1 huge.log)"
elif ! tail -1 huge.log | grep -qx -- "$advice\( (vk[A-Za-z]* returned VK_ERROR_OUT_OF_DEVICE_MEMORY)\)\?"; then
    fail memory.viewport_too_large "$(tail -1 huge.log)"
elif [ -e huge.png ]; then fail memory.viewport_too_large "a screenshot was written"
else ok memory.viewport_too_large; fi

echo "$passed passed, $failed failed"
cd "$scratch" || exit 1
if [ "$failed" -ne 0 ]; then echo "outputs kept in $work"; exit 1; fi
rm -rf -- "$work"
exit 0
