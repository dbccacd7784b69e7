#!/usr/bin/env bash
# Issue 31, finding 6: a user the control socket shuts out was told
# "cannot connect: Permission denied (is uwbd running?)" with exit 69, the
# status for "no daemon". Now: exit 77, one line naming the socket (or the
# directory that stops them), its group, and what to do.
#
# The socket is a listener that never accepts (ctl_attack backlog), so a
# user who may connect gets exit 75 (not accepted in time) instead: the
# permission alone makes the difference. Root passes every permission
# check, so as root the client runs as uid/gid 65534 with no supplementary
# groups (setpriv); as root without setpriv the script is skipped (77).
set -uo pipefail
source tests/e2e/daemon_e2e.sh
e2e_workdir uwbd-ctl-permission

as_user=()
if [[ $(id -u) == 0 ]]; then
    command -v setpriv > /dev/null || { echo "SKIP: running as root and setpriv (util-linux) is missing: no unprivileged user to try"; exit 77; }
    as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups --)
    chmod o+x "$work" # let uid 65534 reach run/
fi
chmod 0755 run

$HOST_PREFIX "$HOST_BUILD/e2e/ctl_attack" backlog run/control.sock 60 > backlog.out 2>&1 &
pids+=($!)
wait_for grep -q "backlog full" backlog.out || fail "no listening socket: $(cat backlog.out)"

# ctl_as_user NAME: `uwbd ctl --socket run/control.sock --timeout 1 status`
# as the unprivileged user; its exit status in $rc, stderr in NAME.err.
ctl_as_user() {
    "${as_user[@]}" ${UWB_EXEC_PREFIX:-} "$BUILD/uwbd" ctl --socket run/control.sock --timeout 1 status \
        > "$1.out" 2> "$1.err"
    rc=$?
}

# ---- the socket shuts the user out ------------------------------------------
if [[ $(id -u) == 0 ]]; then
    chmod 0660 run/control.sock # owner root, group root: uid 65534 is neither
else
    chmod 0000 run/control.sock # not even its owner may connect
fi
group=$(stat -c %G run/control.sock)
ctl_as_user socket
[[ $rc == 77 ]] || fail "socket shut: exit $rc, want 77: $(cat socket.err)"
[[ $(wc -l < socket.err) == 1 && ! -s socket.out ]] || fail "socket shut: want one line on stderr: $(cat socket.err socket.out)"
grep -qF "run/control.sock: permission denied" socket.err || fail "socket shut: the socket is not named: $(cat socket.err)"
grep -qF "group \"$group\"" socket.err || fail "socket shut: its group $group is not named: $(cat socket.err)"
grep -q "is uwbd running" socket.err && fail "socket shut: still blamed on a missing daemon: $(cat socket.err)"
if [[ $(id -u) == 0 ]]; then
    grep -qF "add yourself to group \"$group\"" socket.err || fail "socket shut: no advice: $(cat socket.err)"
else
    grep -qF "shuts out its owner" socket.err || fail "socket shut: no advice: $(cat socket.err)"
fi
pass "a socket the user may not open: exit 77: $(cat socket.err)"

# ---- its directory shuts the user out (/run/uwbd is 0750 uwbd:uwbd) ----------
chmod 0666 run/control.sock
if [[ $(id -u) == 0 ]]; then chmod 0750 run; else chmod 0000 run; fi
dir_group=$(stat -c %G run)
ctl_as_user directory
chmod 0755 run
[[ $rc == 77 ]] || fail "directory shut: exit $rc, want 77: $(cat directory.err)"
grep -qF "directory run (mode" directory.err || fail "directory shut: the directory is not named: $(cat directory.err)"
grep -qF "group \"$dir_group\"" directory.err || fail "directory shut: its group is not named: $(cat directory.err)"
pass "a directory the user may not enter: exit 77: $(cat directory.err)"

# ---- allowed in: the same listener is then only a daemon not accepting -------
ctl_as_user open
[[ $rc == 75 ]] || fail "socket open to all: exit $rc, want 75 (not accepted in time): $(cat open.err)"
pass "the same socket open to the user: exit 75 (the listener never accepts), not 77"

# ---- and no socket at all is still 69 ----------------------------------------
rm -f run/control.sock
ctl_as_user missing
[[ $rc == 69 ]] || fail "no socket: exit $rc, want 69: $(cat missing.err)"
pass "no socket: exit 69, as before"
echo "$passed passed"
