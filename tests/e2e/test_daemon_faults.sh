#!/usr/bin/env bash
# File-system faults against the running daemon and the emulated board. The
# state directory is a tmpfs of its own with the archive on a second one
# inside it, so each can be filled or made read-only:
#   - the archive full while the winding moves: the scan that does not fit
#     is still evaluated (alarm, the contacts say so), its verdict names the
#     file and ENOSPC, `status` says the disk is full until space returns;
#     one whose images do not fit keeps its measurement and says what was
#     not archived (issue 43, break 6);
#   - the archive remounted read-only in the middle of a run;
#   - the whole state directory read-only, then full with a `baseline set`
#     pending (it stays pending);
#   - kill -9 at random moments during archive and baseline writes, many
#     times (UWB_FAULT_KILLS, seeded by UWB_FAULT_SEED).
# After each fault: nothing half-written (tests/e2e/helpers/state_check.c
# reads every file), the baseline byte-identical, the daemon still
# answering, and the next cycle normal once the fault is gone. One daemon
# runs it all (restarted for the kills): under qemu-user a scan takes some
# 10 s, so there the kills default to 2.
#
# The mounts need a private mount namespace: the script re-runs itself under
# `unshare -m` (as root) or `unshare -Urm` (a user namespace otherwise), and
# skips (exit 77) with the reason where neither works.
set -euo pipefail

if [[ -z ${UWB_FAULTS_IN_NAMESPACE:-} ]]; then
    if [[ $(id -u) == 0 ]]; then ns=(unshare -m --propagation private); else ns=(unshare -Urm --propagation private); fi
    probe='d=$(mktemp -d) && mount -t tmpfs -o size=64k uwbd-probe "$d" && umount "$d"; rc=$?; rmdir "$d"; exit $rc'
    if ! command -v unshare > /dev/null; then
        echo "SKIP: unshare (util-linux) is not installed; the file-system faults need a private mount namespace"
        exit 77
    fi
    if ! probe_err=$("${ns[@]}" sh -c "$probe" 2>&1); then
        echo "SKIP: cannot mount a tmpfs in a private mount namespace (${ns[*]}): ${probe_err:-no reason given}"
        echo "SKIP: needs root on a machine (in a chroot / is not a mount point and user namespaces are refused)," \
             "or unprivileged user namespaces (kernel.unprivileged_userns_clone=1)"
        exit 77
    fi
    exec "${ns[@]}" env UWB_FAULTS_IN_NAMESPACE=1 bash "$0" "$@"
fi

# Up to ~60 s for a daemon or board to answer (scans under qemu are slow).
E2E_WAIT_TRIES=600
source "$(dirname "$0")/daemon_e2e.sh"
state_check() { $HOST_PREFIX "$HOST_BUILD/e2e/state_check" "$@"; }

# Under qemu-user every scan is far slower: fewer kills unless asked.
if [[ -n ${UWB_EXEC_PREFIX:-} ]]; then kills=${UWB_FAULT_KILLS:-2}; else kills=${UWB_FAULT_KILLS:-30}; fi
seed=${UWB_FAULT_SEED:-20310417}

work=$(mktemp -d /tmp/uwbd-faults-XXXXXX)
# Our background processes not yet waited for (a reaped pid may be reused).
emu_pid= daemon_pid= killer_pid= load_pid=
cleanup() {
    for pid in $daemon_pid $killer_pid $load_pid $emu_pid; do kill "$pid" 2>/dev/null || true; done
    for pid in $daemon_pid $killer_pid $load_pid $emu_pid; do wait "$pid" 2>/dev/null || true; done
    # The mounts go with the namespace; unmount anyway so rm can remove the mount points.
    grep -o " $work/[^ ]*" /proc/self/mounts | sort -r | while read -r m; do umount -l "$m" || true; done
    rm -rf "$work"
}
trap cleanup EXIT
cd "$work"
mkdir run

get() { state_check get "$@"; }
sha() { sha256sum "$1" | cut -d' ' -f1; }
free_bytes() { df -B1 --output=avail "$1" | tail -n 1 | tr -d ' '; }
lines_of() { if [[ -f $1 ]]; then wc -l < "$1"; else echo 0; fi; }
tree_ok() {
    state_check tree "$@" > tree.out 2> tree.err || fail "state directory damaged: $(cat tree.err)"
}

config="$work/uwbd.json"
cp "$REPO/board/emulated/uwbd.json" "$config"
ctl() { uwbd ctl --socket run/control.sock "$@"; }

# The emulated board with coarse steps (5 per mm) so a scan is mostly imaging,
# and its site lines for the alarm contacts.
$HOST_PREFIX "$HOST_BUILD/uwbemu" --gpio unix:run/gpio.sock --digitiser unix:run/digitiser.sock \
    --control unix:run/emu.sock --site-io unix:run/site.sock --scene "$REPO/tools/uwbsim/scenes/tank-3d.json" --set snr_db=40 --seed 7 \
    --steps-per-mm 5 > emu.log 2>&1 &
emu_pid=$!
wait_for test -S run/emu.sock || fail "uwbemu did not come up"
wait_for uwbemu --ctl unix:run/emu.sock status || fail "uwbemu does not answer"

# Scans on request only, retention off (every file a verdict names stays),
# one pulse per position: the faults need no averaging, and a scan under
# qemu-user takes some 10 s instead of 20.
daemon_args=(--config "$config" "${root_flag[@]}" -v --interval 0 --set carriage.steps_per_mm=5
             --set digitiser.stack=1 --set retention.max_scans=0
             --set site.asset_id=faults --set contacts.enabled=true --set gpio.site_endpoint=unix:run/site.sock)
emu() { uwbemu --ctl unix:run/emu.sock "$*"; }
# The three contacts as the board sees them: "watch alarm fault", 1 = energised.
contacts() { emu status | get lines.watch lines.alarm lines.fault | paste -sd ' '; }
log=uwbd.log
start_daemon() {
    ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" "${daemon_args[@]}" --state-dir "$state" >> "$log" 2>&1 &
    daemon_pid=$!
    wait_for ctl status || fail "uwbd on $state does not answer on its control socket"
}
stop_daemon() {
    kill -TERM "$daemon_pid"
    local rc=0
    wait "$daemon_pid" || rc=$?
    daemon_pid=
    [[ $rc == 0 ]] || fail "uwbd did not stop cleanly on SIGTERM: exit $rc"
}
scan() {   # OUT: one scan, its reply in OUT; the daemon must answer with a VERDICT
    ctl scan > "$1" || fail "scan: $(cat "$1")"
    [[ $(get class < "$1") == VERDICT ]] || fail "scan: $(cat "$1")"
}
last_line() { tail -n 1 "$1" | get "${@:2}"; }

# ---- commissioning on two small file systems --------------------------------
mkdir -p run/state-fs
mount -t tmpfs -o size=8m,mode=0755 uwbd-state run/state-fs
state=$work/run/state-fs/state
archive=$state/archive
mkdir -p "$archive"
mount -t tmpfs -o size=8m,mode=0755 uwbd-archive "$archive"
start_daemon
ctl baseline set > /dev/null
scan commission.json
[[ $(get status baseline_set < commission.json) == $'edges\ntrue' ]] || fail "commissioning: $(cat commission.json)"
base_id=$(get scan_id < commission.json)
base_sum=$(sha "$state/baseline/current.uwbscan")
scan_size=$(stat -c %s "$(get scan_file < commission.json)")
baseline_kept() { [[ $(sha "$state/baseline/current.uwbscan") == "$base_sum" ]] || fail "$1: the baseline changed"; }

# ---- the archive full ----------------------------------------------------------
# Less room than the raw scan needs, and the winding moves 8 mm: the scan is
# still evaluated (issue 43, break 6: it was an `error` verdict, so the
# contacts said fault, not alarm), its verdict names what was not written.
avail=$(free_bytes "$archive")
head -c $((avail - 64 * 1024)) /dev/zero > "$archive/filler"
(($(free_bytes "$archive") < scan_size)) || fail "the filler left $(free_bytes "$archive") bytes, want < $scan_size"
lines_before=$(lines_of "$state/verdicts.jsonl")
verdicts_before=$(sha "$state/verdicts.jsonl")
emu set displacement_m 0.008 > /dev/null
scan full.json
full_id=$(get scan_id < full.json)
[[ $(get status < full.json) == alarm ]] || fail "archive full: status $(get status < full.json), want alarm"
archive_error=$(get archive_error < full.json)
[[ $archive_error == *"$archive/"*"$full_id.uwbscan"*"No space left on device"* ]] ||
    fail "archive full: archive_error does not name the file and ENOSPC: $archive_error"
[[ $(get scan_file < full.json) == "(missing)" ]] || fail "archive full: the verdict names a scan file: $(cat full.json)"
grep -q "scan $full_id: archive (the scan is evaluated all the same): .*$full_id.uwbscan.*No space left on device" "$log" ||
    fail "archive full: no log line naming the file and ENOSPC"
wait_for test "$(contacts)" == "1 1 1" || fail "archive full: contacts (watch alarm fault) $(contacts), want 1 1 1"
[[ $(lines_of "$state/verdicts.jsonl") == $((lines_before + 1)) ]] || fail "archive full: no verdicts.jsonl line"
[[ $(head -n "$lines_before" "$state/verdicts.jsonl" | sha256sum | cut -d' ' -f1) == "$verdicts_before" ]] ||
    fail "archive full: the verdicts recorded before changed"
[[ $(last_line "$state/verdicts.jsonl" scan_id status) == "$full_id"$'\nalarm' ]] ||
    fail "archive full: the last verdicts.jsonl line is not the alarm"
[[ $(get scan_id status < "$state/latest.json") == "$full_id"$'\nalarm' ]] || fail "archive full: latest.json"
ctl status > status.json || fail "the daemon does not answer after the archive filled"
[[ $(get latest.status state_dir_writes.disk_full state_dir_writes.cycles < status.json) == $'alarm\ntrue\n1' ]] ||
    fail "archive full: status does not say the disk is full: $(cat status.json)"
ctl --text status > status.txt
grep -q "^Archive *: NOT WRITING, the disk is full, since .*No space left on device" status.txt ||
    fail "archive full: the status page does not say the disk is full: $(cat status.txt)"
tree_ok "$state" --verdict-files
baseline_kept "archive full"
ctl ack > /dev/null
emu set displacement_m 0 > /dev/null
pass "archive full while the winding moved 8 mm: alarm verdict (contacts 1 1 1) naming the file and" \
     "\"No space left on device\", in verdicts.jsonl (earlier lines intact) and latest.json; status says the" \
     "disk is full; nothing half-written; baseline byte-identical"

# Room for the raw scan but not its images: the measurement stands, the
# verdict names only images that were written and says what was not.
rm "$archive/filler"
avail=$(free_bytes "$archive")
head -c $((avail - scan_size - 96 * 1024)) /dev/zero > "$archive/filler"
scan partial.json
partial_id=$(get scan_id < partial.json)
[[ $(get status < partial.json) == ok ]] || fail "images not archived: status $(get status < partial.json), want ok"
archive_error=$(get archive_error < partial.json)
[[ $archive_error == *"$partial_id-"*".png"*"No space left on device"* ]] ||
    fail "images not archived: archive_error does not name the image and ENOSPC: $archive_error"
grep -q "scan $partial_id: .*png.*No space left on device" "$log" ||
    fail "images not archived: no log line naming the image and ENOSPC"
[[ -f $(get scan_file < partial.json) ]] || fail "images not archived: the raw scan is missing"
tree_ok "$state" --verdict-files
baseline_kept "images not archived"
pass "archive full after the raw scan: status ok kept, archive_error names the image, no image listed that is not there"

rm "$archive/filler"
scan freed.json
[[ $(get status archive_error < freed.json) == $'ok\n(missing)' && $(get images.2 < freed.json) != "(missing)" ]] ||
    fail "after freeing space: $(cat freed.json)"
[[ -f $(get scan_file < freed.json) ]] || fail "after freeing space: the raw scan is not archived"
[[ $(ctl status | get state_dir_writes) == "(missing)" ]] || fail "after freeing space: status still says writes fail"
grep -q "state directory: writing again; 2 scan cycles since .* could not write everything" "$log" ||
    fail "after freeing space: no log line saying writing resumed"
tree_ok "$state" --verdict-files
pass "space freed: the next scan is ok and archived with its three images; status no longer says the disk is full"

# ---- the archive read-only in the middle of the run ------------------------------
# The mount's own read-only flag: a user namespace may set it where it may
# not remount the file system itself.
mount -o remount,bind,ro "$archive"
lines_before=$(lines_of "$state/verdicts.jsonl")
scan ro.json
ro_id=$(get scan_id < ro.json)
[[ $(get status < ro.json) == ok && $(get archive_error < ro.json) == *"$archive/"*"$ro_id.uwbscan"*"Read-only file system"* ]] ||
    fail "read-only archive: $(cat ro.json)"
grep -q "scan $ro_id: archive (the scan is evaluated all the same): .*$ro_id.uwbscan.*Read-only file system" "$log" ||
    fail "read-only archive: no log line naming the file and EROFS"
grep -q "scan $ro_id: archive: .*$ro_id.json.*Read-only file system" "$log" ||
    fail "read-only archive: no log line saying the verdict's archive copy was not written"
[[ $(lines_of "$state/verdicts.jsonl") == $((lines_before + 1)) ]] || fail "read-only archive: verdicts.jsonl"
[[ $(last_line "$state/verdicts.jsonl" scan_id status) == "$ro_id"$'\nok' ]] ||
    fail "read-only archive: the verdict is not in verdicts.jsonl"
ctl status > status.json || fail "the daemon does not answer after the archive went read-only"
[[ $(get state_dir_writes.failing state_dir_writes.disk_full < status.json) == $'true\nfalse' ]] ||
    fail "read-only archive: status: $(cat status.json)"
baseline_kept "read-only archive"
mount -o remount,bind,rw "$archive"
scan rw.json
[[ $(get status < rw.json) == ok ]] || fail "archive writable again: $(cat rw.json)"
tree_ok "$state" --verdict-files
pass "archive read-only: the scan still evaluated, archive_error naming the file (EROFS), status says" \
     "writes fail (not that the disk is full); writable again: the next scan is ok"

# ---- the whole state directory read-only -----------------------------------------
# A read-only bind mount over it (the daemon's open lock file would keep a
# remount from going read-only): nowhere to record the verdict.
mount --bind "$state" "$state"
mount -o remount,bind,ro "$state"
lines_before=$(lines_of "$state/verdicts.jsonl")
scan state-ro.json
ro_id=$(get scan_id < state-ro.json)
[[ $(get status < state-ro.json) == ok && $(get archive_error < state-ro.json) == *"Read-only file system"* ]] ||
    fail "state read-only: $(cat state-ro.json)"
[[ $(get record_error < state-ro.json) == *"$state/verdicts.jsonl"*"Read-only file system"* ]] ||
    fail "state read-only: the verdict does not say it is not in verdicts.jsonl: $(cat state-ro.json)"
grep -q "scan $ro_id: verdict log: $state/verdicts.jsonl: .*Read-only file system" "$log" ||
    fail "state read-only: no log line for the verdict log"
ctl status > status.json
ctl verdict > verdict.json
[[ $(get latest.scan_id latest.status < status.json) == "$ro_id"$'\nok' ]] ||
    fail "state read-only: status: $(cat status.json)"
cmp -s state-ro.json verdict.json || fail "state read-only: \`verdict\` is not the scan's reply"
[[ $(lines_of "$state/verdicts.jsonl") == "$lines_before" ]] || fail "state read-only: verdicts.jsonl changed"
baseline_kept "state read-only"
umount "$state"
scan state-rw.json
[[ $(get status < state-rw.json) == ok ]] || fail "state writable again: $(cat state-rw.json)"
tree_ok "$state" --verdict-files
pass "state directory read-only: the verdict (ok) in the reply, status and log, record_error says it is" \
     "not in verdicts.jsonl; writable again: the next scan is ok"

# ---- the whole state directory full, `baseline set` pending ------------------------
head -c 1G /dev/zero > run/state-fs/filler 2> /dev/null || true   # each stops at ENOSPC
head -c 1G /dev/zero > "$archive/filler" 2> /dev/null || true
[[ $(free_bytes run/state-fs) == 0 && $(free_bytes "$archive") == 0 ]] ||
    fail "the fillers left $(free_bytes run/state-fs) and $(free_bytes "$archive") bytes"
lines_before=$(lines_of "$state/verdicts.jsonl")
ctl baseline set > /dev/null
scan state-full.json
full_id=$(get scan_id < state-full.json)
[[ $(get status < state-full.json) == ok && $(get archive_error < state-full.json) == *"No space left on device"* ]] ||
    fail "state full: $(cat state-full.json)"
[[ $(get baseline_set baseline_note < state-full.json) == $'false\nnot set: the scan could not be archived'* ]] ||
    fail "state full: the verdict does not say why the baseline was not set: $(cat state-full.json)"
grep -q "scan $full_id: archive (the scan is evaluated all the same): .*No space left on device" "$log" ||
    fail "state full: no log line"
ctl status > status.json
[[ $(get latest.scan_id latest.status baseline_pending baseline.scan_id state_dir_writes.disk_full < status.json) == \
   "$full_id"$'\nok\ntrue\n'"$base_id"$'\ntrue' ]] || fail "state full: status: $(cat status.json)"
ctl verdict > verdict.json
cmp -s state-full.json verdict.json || fail "state full: \`verdict\` is not the scan's reply"
# verdicts.jsonl may still take the line in the room its last page had left;
# when it does not, the verdict says so.
if [[ $(lines_of "$state/verdicts.jsonl") == "$lines_before" ]]; then
    [[ $(get record_error < state-full.json) == *verdicts.jsonl*"No space left on device"* ]] ||
        fail "state full: the verdict was not logged and does not say so: $(cat state-full.json)"
    where="reply, status and log (record_error: not in verdicts.jsonl)"
else
    [[ $(last_line "$state/verdicts.jsonl" scan_id) == "$full_id" ]] || fail "state full: verdicts.jsonl"
    where="reply, status, log and verdicts.jsonl"
fi
baseline_kept "state full"
tree_ok "$state" --verdict-files
pass "state directory full: the verdict (ok) in the $where; status says the disk is full;" \
     "baseline byte-identical, still pending"

rm run/state-fs/filler "$archive/filler"
started=$EPOCHREALTIME
scan state-freed.json
cycle_ms=$(awk -v a="$started" -v b="$EPOCHREALTIME" 'BEGIN { printf "%d", (b - a) * 1000 }')
[[ $(get status baseline_set < state-freed.json) == $'ok\ntrue' ]] || fail "after freeing space: $(cat state-freed.json)"
[[ $(sha "$state/baseline/history/$base_id.uwbscan") == "$base_sum" ]] || fail "the old baseline is not in history"
cmp -s "$state/baseline/current.uwbscan" "$(get scan_file < state-freed.json)" ||
    fail "the new baseline is not the scan that became it"
tree_ok "$state" --verdict-files
pass "space freed: the next scan is ok and becomes the pending baseline; the old one kept in history"

# ---- kill -9 during archive and baseline writes, again and again ----------------
# On the disk rather than tmpfs, where writes take their fsyncs' time: a new
# state directory that starts from a copy of this one's baseline.
stop_daemon
mkdir run/kill
cp -a "$state/baseline" run/kill/
state=$work/run/kill
log=uwbd-kill.log
start_daemon
[[ $(ctl status | get baseline.scan_id) == "$(get scan_id < state-freed.json)" ]] ||
    fail "the daemon does not take the copied baseline"
# Three kills in four come while a file is being written: state_check
# kill-on-write watches the directories and kills at the n-th write of a
# cycle (a temporary created, or the verdicts.jsonl append; n at random),
# after a random 0-4 ms. The fourth kill comes at a random time within two
# cycles. Nothing about time is asserted: the delays only spread the kills.
day=$(dirname "$(get scan_file < state-freed.json)")
day_dir=$state/archive/${day#"$archive/"}   # created now, so it can be watched from the start
mkdir -p "$day_dir"
watched=("$day_dir" "$state" "$state/baseline" "$state/baseline/history")
RANDOM=$seed
base_sum=$(sha "$state/baseline/current.uwbscan")
base_id=$(get scan_id < state-freed.json)
lines=$(lines_of "$state/verdicts.jsonl")
mid_write=0 baseline_changes=0
declare -A hits=()
for i in $(seq "$kills"); do
    # A cycle writes the raw scan, 3 images, [history scan and json,
    # current.uwbscan and json,] its verdict file, a verdicts.jsonl line and
    # latest.json: rounds with `baseline set` aim at the bracketed four.
    if ((i % 2)); then skip=$((4 + RANDOM % 4)); else skip=$((RANDOM % 7)); fi
    if ((RANDOM % 4)); then
        delay_us=$((RANDOM % 4000))
        how="at write $((skip + 1)) + $delay_us us"
        state_check kill-on-write "$daemon_pid" "$skip" "$delay_us" $((4 * cycle_ms / 1000 + 30)) "${watched[@]}" \
            > kill-on-write.out 2>&1 &
        killer_pid=$!
    else
        delay_ms=$((RANDOM % (2 * cycle_ms + 1)))
        how="at $delay_ms ms"
    fi
    # A `baseline set` of an earlier round that a kill interrupted stays
    # pending (baseline/pending.json) and may be applied in this round.
    asked_before=0
    [[ -e $state/baseline/pending.json ]] && asked_before=1
    if ((i % 2)); then
        (ctl baseline set; ctl scan; ctl baseline set; ctl scan) > /dev/null 2>&1 &
    else
        (ctl scan; ctl scan) > /dev/null 2>&1 &
    fi
    load_pid=$!
    if [[ -n $killer_pid ]]; then
        killed=0
        wait "$killer_pid" 2> /dev/null || killed=$?
        killer_pid=
        if ((killed == 0)); then
            hit=$(cat kill-on-write.out)
            how+=" (${hit#"$state/"})"
            case $hit in
                */history/*) hits[history]=$((hits[history] + 1)) ;;
                */baseline/.current.uwbscan.*) hits[current.uwbscan]=$((hits[current.uwbscan] + 1)) ;;
                */baseline/.current.json.*) hits[current.json]=$((hits[current.json] + 1)) ;;
                */verdicts.jsonl) hits[verdicts.jsonl]=$((hits[verdicts.jsonl] + 1)) ;;
                */.latest.json.*) hits[latest.json]=$((hits[latest.json] + 1)) ;;
                *.png.*) hits[image]=$((hits[image] + 1)) ;;
                *.uwbscan.*) hits[raw scan]=$((hits[raw scan] + 1)) ;;
                *.json.*) hits[verdict file]=$((hits[verdict file] + 1)) ;;
            esac
        else
            how+=" (no such write: killed after it)"
        fi
    else
        sleep "$(awk -v ms="$delay_ms" 'BEGIN { printf "%.3f", ms / 1000 }')"
    fi
    kill -9 "$daemon_pid" 2> /dev/null || true
    wait "$daemon_pid" 2> /dev/null || true
    daemon_pid=
    wait "$load_pid" || true
    load_pid=
    temps=$(find "$state" -name '.*' -type f | wc -l)
    ((temps == 0)) || mid_write=$((mid_write + 1))

    log_lines=$(lines_of "$log")
    start_daemon
    if ((temps > 0)); then
        tail -n +$((log_lines + 1)) "$log" | grep -q "removed [0-9]* leftover" ||
            fail "kill $i: $temps temporaries were left and the restart did not say it removed them"
    fi
    state_check tree "$state" --verdict-files > tree.out 2> tree.err ||
        fail "kill $i ($how, seed $seed): $(cat tree.err)"
    now_lines=$(lines_of "$state/verdicts.jsonl")
    ((now_lines >= lines)) || fail "kill $i: verdicts.jsonl lost lines ($lines -> $now_lines)"
    lines=$now_lines

    # The baseline is the one before the kill, byte for byte, or a scan that
    # became the baseline in this round: then the archived copy of that scan
    # is byte-identical, and the one it replaced is kept in history.
    now_sum=$(sha "$state/baseline/current.uwbscan")
    now_id=$(head -n 1 "$state/baseline/current.uwbscan" | get scan_id)
    if [[ $now_sum != "$base_sum" ]]; then
        ((i % 2 || asked_before)) || fail "kill $i: the baseline changed in a round without \`baseline set\`"
        archived=$(find "$state/archive" -name "$now_id.uwbscan")
        [[ -n $archived ]] && cmp -s "$archived" "$state/baseline/current.uwbscan" ||
            fail "kill $i: the new baseline $now_id is not a whole archived scan"
        [[ $(sha "$state/baseline/history/$base_id.uwbscan") == "$base_sum" ]] ||
            fail "kill $i: the replaced baseline $base_id is not whole in history"
        base_sum=$now_sum base_id=$now_id
        baseline_changes=$((baseline_changes + 1))
    fi
    [[ $now_id == "$base_id" ]] || fail "kill $i: current.uwbscan names $now_id, want $base_id"
    ctl status > status-kill.json
    [[ $(get baseline.scan_id < status-kill.json) == "$base_id" ]] ||
        fail "kill $i: status names baseline $(get baseline.scan_id < status-kill.json), want $base_id"
done
scan kill-after.json
[[ $(get status < kill-after.json) == ok ]] || fail "the scan after $kills kills: $(cat kill-after.json)"
tree_ok "$state" --verdict-files
stop_daemon
hit_list=$(for k in "${!hits[@]}"; do printf '%s %s, ' "${hits[$k]}" "$k"; done)
echo "kill -9: $kills kills (seed $seed); while writing: ${hit_list%, }; $mid_write left temporaries" \
     "(swept at restart); $baseline_changes baseline changes, $(grep -c "rebuilt it from the scan" "$log" || true)" \
     "current.json rebuilt; $lines verdict lines for $(find "$state/archive" -name '*.uwbscan' | wc -l) archived scans"
pass "kill -9 x $kills during archive and baseline writes: every file whole after each restart," \
     "verdicts.jsonl parses, baseline intact (old or a whole new one); the next scan ok"

echo "$passed passed, 0 failed"
