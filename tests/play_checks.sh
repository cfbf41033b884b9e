#!/usr/bin/env bash
# End-to-end checks of `brume play`: split frame ranges reproduce a full run byte for byte, the
# video is encoded, an interrupted run leaves only complete frames, bad ranges are refused.
# Usage: play_checks.sh BRUME SCRATCH_DIR
set -u
brume=$1
scratch=$2
case $brume in /*) ;; *) brume=$PWD/$brume ;; esac  # the checks run in their own directory
presets=$(cd "$(dirname "${BASH_SOURCE[0]}")/../presets" && pwd) || exit 2
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
    for p in plume ground-fog campfire explosion fog-bank crossing layers low-sun pop vdb-cloud; do
        printf '%s\n' "$out" | grep -q "^$p " || missing="$missing $p"
    done
    if [ -n "$missing" ]; then fail list "missing:$missing"
    elif ! printf '%s\n' "$out" | grep -q "(default)"; then fail list "no default marked"
    elif ! printf '%s\n' "$out" | grep -q "^fog-bank  *168 frames (" ; then fail list "no frame count: $(printf '%s\n' "$out" | grep fog-bank)"
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
# "-" reads the preset from standard input (a generator's pipe): the same frames as the built-in's.
"$brume" play - -o from_stdin --frames 0-1 "${small[@]}" <"$presets/crossing.toml" >from_stdin.log 2>&1 ||
    fail preset_from_stdin "exit $?: $(tail -1 from_stdin.log)"
if cmp -s full/crossing.0001.exr from_stdin/crossing.0001.exr && cmp -s full/crossing.0001.png from_stdin/crossing.0001.png; then
    ok preset_from_stdin
else
    fail preset_from_stdin "frame 1 from standard input differs: $(ls from_stdin 2>&1 | tr '\n' ' ')"
fi
# A farm job held to one CPU (--threads 1, or an affinity of one CPU as Slurm and taskset give) renders
# the same frames, byte for byte: the tracers' images do not depend on their thread count.
"$brume" play crossing -o one_thread --frames 4-5 --threads 1 "${small[@]}" >one_thread.log 2>&1 ||
    fail farm.one_thread "exit $?: $(tail -1 one_thread.log)"
diffs=""
for f in 0004 0005; do
    for ext in png exr; do cmp -s "full/crossing.$f.$ext" "one_thread/crossing.$f.$ext" || diffs="$diffs crossing.$f.$ext"; done
done
if [ -z "$diffs" ]; then ok farm.one_thread; else fail farm.one_thread "differ:$diffs"; fi
if command -v taskset >/dev/null 2>&1; then
    # The first CPU this shell may use (a container's cpuset need not hold CPU 0).
    first_cpu=$(taskset -cp $$ | sed 's/.*: *//; s/[,-].*//')
    taskset -c "$first_cpu" "$brume" play crossing -o one_cpu --frames 5 "${small[@]}" >one_cpu.log 2>&1 ||
        fail farm.one_cpu "exit $?: $(tail -1 one_cpu.log)"
    if cmp -s full/crossing.0005.exr one_cpu/crossing.0005.exr && cmp -s full/crossing.0005.png one_cpu/crossing.0005.png; then
        ok farm.one_cpu
    else
        fail farm.one_cpu "frame 5 on one CPU differs from the full run's"
    fi
fi

# Video: an MP4 (ISO base media: 'ftyp' at byte 4) of the frames.
if command -v ffmpeg >/dev/null 2>&1; then
    if "$brume" play crossing -o vid --frames 0-5 --size 64x48 --video vid/crossing.mp4 >vid.log 2>&1 &&
        [ "$(head -c 8 vid/crossing.mp4 2>/dev/null | tail -c 4)" = "ftyp" ]; then
        if [ -e vid/crossing.ffmpeg.log ] || ls -A vid | grep -q '^\.'; then
            fail video "a good encoding left its log or a temporary file: $(ls -A vid | tr '\n' ' ')"
        else
            ok video
        fi
    else
        fail video "$(tail -2 vid.log)"
    fi
else
    echo "skip video: ffmpeg not installed"
fi

# A failed encoding keeps NAME.ffmpeg.log beside the frames and names it, with its last line, in the one error
# line every failure gets; the frames stay, and neither a
# video nor a temporary file is left. Brume finds ffmpeg on PATH, so a stand-in that answers -version and
# fails to encode makes the encoding fail after the frames are written (no real ffmpeg needed).
mkdir -p fakebin
printf '%s\n' '#!/bin/sh' 'for a in "$@"; do [ "$a" = -version ] && { echo "ffmpeg version stand-in"; exit 0; }; done' \
    'echo "stand-in ffmpeg: cannot encode" >&2' 'exit 1' >fakebin/ffmpeg
chmod +x fakebin/ffmpeg
PATH=$work/fakebin:$PATH "$brume" play crossing -o vfail --frames 0-1 --size 16x12 --video vfail/crossing.mp4 >vfail.log 2>vfail.err
rc=$?
first=$(head -n 1 vfail.err)
held=$(ls -A vfail 2>/dev/null | tr '\n' ' ')
if [ "$rc" -ne 1 ]; then fail video_failed_keeps_log "exit status $rc: $first"
elif [ "$(wc -l <vfail.err)" -ne 1 ] ||
     [ "$first" != 'brume: error: ffmpeg failed (exit 1) encoding vfail/crossing.mp4; its log vfail/crossing.ffmpeg.log ends with "stand-in ffmpeg: cannot encode"' ]; then
    fail video_failed_keeps_log "message ($(wc -l <vfail.err) lines): $first"
elif ! grep -qx "stand-in ffmpeg: cannot encode" vfail/crossing.ffmpeg.log 2>/dev/null; then fail video_failed_keeps_log "no log kept: $held"
elif [ "$held" != "crossing.0000.png crossing.0001.png crossing.ffmpeg.log " ]; then fail video_failed_keeps_log "the folder holds: $held"
else ok video_failed_keeps_log; fi
# A good encoding into the same folder afterwards removes the failed one's log.
if command -v ffmpeg >/dev/null 2>&1; then
    if "$brume" play crossing -o vfail --frames 0-1 --size 16x12 --video vfail/crossing.mp4 >vgood.log 2>&1 &&
        [ "$(head -c 8 vfail/crossing.mp4 2>/dev/null | tail -c 4)" = "ftyp" ]; then
        held=$(ls -A vfail | tr '\n' ' ')
        if [ "$held" != "crossing.0000.png crossing.0001.png crossing.mp4 " ]; then fail video_good_removes_old_log "the folder holds: $held"
        else ok video_good_removes_old_log; fi
    else
        fail video_good_removes_old_log "$(tail -2 vgood.log)"
    fi
else
    echo "skip video_good_removes_old_log: ffmpeg not installed"
fi
# The video is an output like any other (render/atomic_file.h): a FIFO is written into, not replaced; a
# replaced file keeps its permissions; the frames' folder may be named "ts/" (tab completion's form) or
# hold a '%', which ffmpeg's frame pattern must not read as a conversion.
if command -v ffmpeg >/dev/null 2>&1; then
    mkfifo vfifo.mp4
    timeout 60 cat vfifo.mp4 >vfifo_read.mp4 &  # bounded: a run that never opens the FIFO leaves it waiting
    reader=$!
    "$brume" play crossing -o vfifo --frames 0-1 --size 16x12 --video vfifo.mp4 >vfifo.log 2>&1
    rc=$?
    wait "$reader"
    if [ "$rc" -eq 0 ] && [ -p vfifo.mp4 ] && [ "$(head -c 8 vfifo_read.mp4 | tail -c 4)" = "ftyp" ]; then ok video_fifo_written_into
    else fail video_fifo_written_into "rc $rc, $(stat -c %F vfifo.mp4), $(tail -1 vfifo.log)"; fi
    : >vmode.mp4
    chmod 600 vmode.mp4
    "$brume" play crossing -o vmode --frames 0-1 --size 16x12 --video vmode.mp4 >vmode.log 2>&1 &&
        [ "$(stat -c %a vmode.mp4)" = 600 ] && [ -s vmode.mp4 ] && ok video_keeps_permissions ||
        fail video_keeps_permissions "mode $(stat -c %a vmode.mp4): $(tail -1 vmode.log)"
    "$brume" play crossing -o vslash/ --frames 0-1 --size 16x12 --video vslash/crossing.mp4 >vslash.log 2>&1 &&
        [ -s vslash/crossing.mp4 ] && ok video_in_folder_named_with_slash ||
        fail video_in_folder_named_with_slash "$(tail -1 vslash.log)"
    "$brume" play crossing -o 'v%d' --frames 0-1 --size 16x12 --video 'v%d/crossing.mp4' >vpercent.log 2>&1 &&
        [ -s 'v%d/crossing.mp4' ] && ok video_folder_with_percent || fail video_folder_with_percent "$(tail -1 vpercent.log)"
else
    echo "skip video_fifo_written_into, video_keeps_permissions, video_in_folder_named_with_slash, video_folder_with_percent: ffmpeg not installed"
fi
# Ctrl-C while the video encodes (a stand-in ffmpeg interrupts brume, its parent, and exits as ffmpeg does
# on SIGINT): exit 130 and a line saying so, not "ffmpeg failed" with a log; the frames complete, no video.
mkdir -p intbin
printf '%s\n' '#!/bin/sh' 'for a in "$@"; do [ "$a" = -version ] && { echo "ffmpeg version stand-in"; exit 0; }; done' \
    'kill -INT "$PPID"' 'sleep 1' 'exit 255' >intbin/ffmpeg
chmod +x intbin/ffmpeg
PATH=$work/intbin:$PATH "$brume" play crossing -o vint --frames 0-1 --size 16x12 --video vint/crossing.mp4 >vint.log 2>vint.err
rc=$?
held=$(ls -A vint 2>/dev/null | tr '\n' ' ')
if [ "$rc" -eq 130 ] && grep -q "interrupted while encoding vint/crossing.mp4" vint.err && ! grep -q "ffmpeg failed" vint.err &&
    [ "$held" = "crossing.0000.png crossing.0001.png " ]; then ok video_interrupted
else fail video_interrupted "rc $rc, folder: $held, stderr: $(head -c 300 vint.err)"; fi

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

# An output folder, or the folder it is made in, may hold anything, a directory named "probe" included:
# the check before the first frame once asked whether a made-up file of that name could be written.
mkdir -p holder/probe parent/probe
"$brume" play crossing -o holder --frames 0 --size 16x12 >holder.log 2>&1
rc1=$?
"$brume" play crossing -o parent/new --frames 0 --size 16x12 >parent.log 2>&1
rc2=$?
if [ "$rc1" -ne 0 ] || [ ! -s holder/crossing.0000.png ] || [ ! -d holder/probe ]; then
    fail folder_holding_probe "rc $rc1: $(tail -1 holder.log)"
elif [ "$rc2" -ne 0 ] || [ ! -s parent/new/crossing.0000.png ]; then
    fail folder_holding_probe "a new folder beside it, rc $rc2: $(tail -1 parent.log)"
else ok folder_holding_probe; fi
# A folder that cannot be made (its would-be parent is a file) is refused before any work.
: >afile
"$brume" play crossing -o afile/out --frames 0 --size 16x12 >afile.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "afile is not a directory" afile.log; then ok bad.output_under_a_file; else fail bad.output_under_a_file "rc $rc: $(tail -1 afile.log)"; fi

# A frame's name that is taken by a directory is refused before the first frame, not after the frames
# before it.
mkdir -p taken/crossing.0001.png
"$brume" play crossing -o taken --frames 0-2 --size 16x12 >taken.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q "taken/crossing.0001.png: it is a directory" taken.log && [ ! -e taken/crossing.0000.png ]; then
    ok bad.frame_name_taken
else fail bad.frame_name_taken "rc $rc, holds: $(ls -A taken | tr '\n' ' '): $(tail -1 taken.log)"; fi

# SIGHUP (a closed terminal) ends a run as SIGINT does: the frame in progress is finished, exit 130
# (issue 14 item 13; it used to kill at once).
"$brume" play plume -o hup --size 64x48 --format png,exr >hup.log 2>&1 &
pid=$!
for _ in $(seq 1 200); do
    [ -e hup/plume.0000.png ] && break
    sleep 0.05
done
kill -HUP "$pid" 2>/dev/null
wait "$pid"
rc=$?
# stopped_as_on_a_signal DIR LOG: the run (status $rc) stopped as on a signal: exit 130, "interrupted" in
# LOG, every PNG in DIR with its EXR and no temporaries; "" or why not, as the check's failure.
stopped_as_on_a_signal() {
    local dir=$1 log=$2 f unpaired=""
    for f in "$dir"/*.png; do [ -e "${f%.png}.exr" ] || unpaired="$unpaired $f"; done
    for f in "$dir"/*.exr; do [ -e "${f%.exr}.png" ] || unpaired="$unpaired $f"; done
    if [ "$rc" -ne 130 ]; then echo "exit status $rc, expected 130: $(tail -c 300 "$log")"
    elif [ -n "$unpaired" ] || ls -A "$dir" | grep -q '^\.'; then echo "unpaired or temporary files:$unpaired"
    elif ! grep -q "interrupted" "$log"; then echo "no message: $(tail -c 300 "$log")"
    fi
}
why=$(stopped_as_on_a_signal hup hup.log)
if [ -n "$why" ]; then fail sighup "$why"; else ok sighup; fi

# A log pipe whose reader went away (`play ... | head -1`, a dropped ssh session's pipe) ends a run as
# SIGHUP does: the frame in progress finished, a message on stderr, exit 130; not a kill by SIGPIPE.
( "$brume" play plume -o piped --size 64x48 --format png,exr 2>piped.err; echo $? >piped.rc ) | head -c 1 >/dev/null
rc=$(cat piped.rc)
why=$(stopped_as_on_a_signal piped piped.err)
if [ -n "$why" ]; then fail log_pipe_closed "$why"
elif [ "$(ls piped | wc -l)" -ge 288 ]; then fail log_pipe_closed "every frame was rendered"
else ok log_pipe_closed; fi

# Ctrl-C during a long preroll stops it within moments, and nothing is written (issue 14 item 9).
cat >long_preroll.toml <<'EOF'
[timeline]
fps = 24.0
duration = 1.0
substeps = 4
preroll = 3600.0
[[emitter]]
shape = "point"
center = [0.0, 0.5, 0.0]
rate = 2000.0
lifetime = 5.0
particle_radius = 0.1
extinction = 1.0
EOF
"$brume" play long_preroll.toml -o preroll --size 16x12 >preroll.log 2>&1 &
pid=$!
sleep 2
kill -INT "$pid" 2>/dev/null
stopped=no
for _ in $(seq 1 100); do
    kill -0 "$pid" 2>/dev/null || { stopped=yes; break; }
    sleep 0.05
done
if [ "$stopped" = no ]; then
    kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    fail preroll_interrupt "still running 5 s after SIGINT"
else
    wait "$pid"
    rc=$?
    if [ "$rc" -ne 130 ]; then fail preroll_interrupt "exit status $rc: $(tail -1 preroll.log)"
    elif [ -e preroll ]; then fail preroll_interrupt "an interrupted preroll created its output folder"
    elif ! grep -q "interrupted during the simulation" preroll.log; then fail preroll_interrupt "$(tail -1 preroll.log)"
    else ok preroll_interrupt; fi
fi

# The summary's simulation time includes the preroll (issue 14 item 9): a 60 s preroll of 2,000 particles
# a second takes a measurable time, which the summary states, never more than the run took.
# The long-preroll preset above, with a 60 s preroll and half a second of frames.
sed -e 's/^duration = .*/duration = 0.5/' -e 's/^preroll = .*/preroll = 60.0/' long_preroll.toml >sim_time.toml
t0=$(date +%s.%N)
"$brume" play sim_time.toml -o sim_time --frames 0 --size 8x6 >sim_time.log 2>&1
rc=$?
t1=$(date +%s.%N)
sim_s=$(sed -n 's/^wrote 1 frame in [0-9.]* s (simulation \([0-9.]*\) s) to sim_time$/\1/p' sim_time.log)
if [ "$rc" -ne 0 ]; then fail preroll_summary "exit status $rc: $(tail -1 sim_time.log)"
elif [ -z "$sim_s" ]; then fail preroll_summary "no 'wrote 1 frame in X s (simulation Y s)' line: $(tail -1 sim_time.log)"
elif ! awk -v s="$sim_s" -v w="$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f", b - a }')" 'BEGIN { exit !(s > 0 && s <= w) }'; then
    fail preroll_summary "simulation $sim_s s for a 60 s preroll (the run took $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }') s)"
else ok preroll_summary; fi

# The conversion cache end to end (README "Farms"): with BRUME_CACHE_DIR set, the second job of vdb-cloud
# reads the spheres the first converted, says so, and renders the same bytes; so does a job of other
# frames. BRUME_CACHE=off converts again.
cache=$work/cache
cached_play() { env -u BRUME_CACHE BRUME_CACHE_DIR="$cache" "$brume" play vdb-cloud --size 8x6 "$@"; }
cached_play --frames 0 -o cache1 >cache1.log 2>&1
rc1=$?
cached_play --frames 0 -o cache2 >cache2.log 2>&1
rc2=$?
cached_play --frames 1 -o cache3 >cache3.log 2>&1
rc3=$?
BRUME_CACHE=off BRUME_CACHE_DIR="$cache" "$brume" play vdb-cloud --size 8x6 --frames 0 -o cache4 >cache4.log 2>&1
rc4=$?
conv='^builtin:cloud: [0-9]* spheres from [0-9]* active voxels, optical-depth error .*, [0-9.]* s'
entries=$(ls -A "$cache" 2>/dev/null | tr '\n' ' ')
if [ "$rc1$rc2$rc3$rc4" != 0000 ]; then fail conversion_cache "exit statuses $rc1 $rc2 $rc3 $rc4: $(tail -1 cache1.log)"
elif ! grep -q "$conv\$" cache1.log; then fail conversion_cache "the first job did not convert: $(head -1 cache1.log)"
elif ! grep -q "$conv (from the conversion cache)\$" cache2.log; then fail conversion_cache "the second job did not say it read the cache: $(head -1 cache2.log)"
elif ! grep -q "$conv (from the conversion cache)\$" cache3.log; then fail conversion_cache "a job of other frames did not read the cache: $(head -1 cache3.log)"
elif ! grep -q "$conv\$" cache4.log; then fail conversion_cache "BRUME_CACHE=off still read the cache: $(head -1 cache4.log)"
elif ! cmp -s cache1/vdb-cloud.0000.png cache2/vdb-cloud.0000.png; then fail conversion_cache "the cached job's frame differs"
elif ! cmp -s cache1/vdb-cloud.0000.png cache4/vdb-cloud.0000.png; then fail conversion_cache "the uncached job's frame differs"
elif [ "$(ls -A "$cache" | wc -l)" -ne 1 ] || ! ls -A "$cache" | grep -q '^[0-9a-f]*\.spheres$'; then fail conversion_cache "the cache holds: $entries"
else ok conversion_cache; fi

# A full particle budget is said once and counted (issue 14 item 4).
cat >capped.toml <<'EOF'
[timeline]
fps = 10.0
duration = 0.5
max_particles = 5
[[emitter]]
shape = "point"
center = [0.0, 0.5, 0.0]
rate = 150.0
lifetime = 10.0
particle_radius = 0.1
extinction = 1.0
EOF
"$brume" play capped.toml -o capped --size 16x12 >capped.log 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then fail budget_note "exit status $rc: $(tail -1 capped.log)"
elif [ "$(grep -c "max_particles = 5 is full" capped.log)" -ne 1 ]; then fail budget_note "not said once: $(head -3 capped.log)"
elif ! grep -Eq "skipped [1-9][0-9]* births" capped.log; then fail budget_note "no count: $(tail -2 capped.log)"
else ok budget_note; fi

# A refused or failed run creates no output folder; a video name ffmpeg cannot write is refused first.
"$brume" play crossing -o nodir_device --device no-such-device >nd.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && [ ! -e nodir_device ]; then ok failed_run_no_folder; else fail failed_run_no_folder "rc $rc, folder: $(ls -d nodir_device 2>&1)"; fi
"$brume" play crossing -o gif --frames 0-1 --size 16x12 --video gif/out.gif >gif.log 2>&1
rc=$?
if [ "$rc" -ne 0 ] && grep -q ".mp4" gif.log && [ ! -e gif ]; then ok video_name_checked_first; else fail video_name_checked_first "rc $rc: $(tail -1 gif.log)"; fi
"$brume" play crossing -o frame_video --frames 0-1 --size 16x12 --video frame_video/crossing.0000.png >fv.log 2>&1
rc=$?
if [ "$rc" -eq 2 ] && [ "$(cat fv.log)" = "brume: error: --video frame_video/crossing.0000.png: the video is H.264, so its name must end in .mp4, .mkv, .mov or .m4v (not .png)" ] &&
    [ ! -e frame_video ]; then ok video_not_a_frame; else fail video_not_a_frame "rc $rc: $(tail -1 fv.log)"; fi

echo "$passed passed, $failed failed"
cd "$scratch" || exit 1
if [ "$failed" -ne 0 ]; then echo "outputs kept in $work"; exit 1; fi
rm -rf -- "$work"
exit 0
