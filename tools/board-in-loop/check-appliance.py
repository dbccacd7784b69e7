#!/usr/bin/env python3
"""Checks the appliance boot of make test-board.

Reads the guest's console (the BOARD-REPLY lines guest-appliance.sh prints)
and the emulated board's status taken on the host after the guest powered
off; prints one PASS or FAIL line per claim, in the style of
tests/run-tests.sh, and exits with the number of failed claims.

Usage: check-appliance.py CONSOLE_LOG EMU_STATUS_JSON SHIFT_MM POSITIONS STACK
"""
import json
import sys

TOLERANCE_MM = 0.5


def replies_from(console_path):
    """NAME -> (exit status, reply text) from 'BOARD-REPLY NAME STATUS TEXT'."""
    replies = {}
    with open(console_path, encoding="utf-8", errors="replace") as console:
        for line in console:
            if not line.startswith("BOARD-REPLY "):
                continue
            parts = line.rstrip("\n").split(" ", 3)
            if len(parts) >= 3:
                replies[parts[1]] = (parts[2], parts[3] if len(parts) == 4 else "")
    return replies


class Checker:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def claim(self, name, check):
        """check() returns a note for the PASS line or raises with the reason."""
        try:
            note = check()
        except Exception as error:  # every failure is reported, none stops the rest
            self.failed += 1
            print(f"FAIL  board/appliance: {name}: {error}")
            return
        self.passed += 1
        print(f"PASS  board/appliance: {name}" + (f"  ({note})" if note else ""))


def json_reply(replies, name, want_status="0"):
    if name not in replies:
        raise AssertionError(f"no '{name}' reply on the console (the guest's job stopped before it)")
    status, text = replies[name]
    if status != want_status:
        raise AssertionError(f"exit status {status}: {text[:300]}")
    return json.loads(text)


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    console_path, status_path = sys.argv[1], sys.argv[2]
    shift_mm, positions, stack = float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    replies = replies_from(console_path)
    check = Checker()

    def daemon_up():
        if replies.get("daemon-start", ("1",))[0] != "0":
            raise AssertionError(replies.get("daemon-start", ("", "no start line"))[1])
        return "aarch64 uwbd answered uwbd ctl on its control socket"

    def commissioning():
        pending = json_reply(replies, "baseline-set")
        assert pending["class"] == "BASELINE" and pending["pending"] is True, pending
        verdict = json_reply(replies, "baseline-scan")
        assert verdict["class"] == "VERDICT", verdict
        assert verdict["status"] == "edges" and verdict["baseline_set"] is True, verdict
        return (f"baseline {verdict['scan_id']}: edges {verdict['lower_edge_mm']:.2f}.."
                f"{verdict['upper_edge_mm']:.2f} mm")

    def shift_requested():
        status, text = replies.get("emu-control", ("", "no reply"))
        assert '"class":"OK"' in text, f"uwbemu's control endpoint over the UART answered: {text!r}"
        return f"uwbemu control over the third UART: set displacement_m {shift_mm / 1000:g}"

    def shifted():
        verdict = json_reply(replies, "shifted-scan")
        assert verdict["class"] == "VERDICT" and verdict["status"] == "alarm", verdict
        measured = verdict["axial_displacement_mm"]
        assert abs(measured - shift_mm) <= TOLERANCE_MM, (
            f"displacement {measured:+.2f} mm for an emulated shift of {shift_mm:+.2f} mm "
            f"(tolerance {TOLERANCE_MM} mm)")
        return (f"measured {measured:+.2f} ± {verdict['uncertainty_mm']:.2f} mm for {shift_mm:+.2f} mm, "
                f"status {verdict['status']}")

    def history():
        reply = json_reply(replies, "history")
        statuses = [entry["status"] for entry in reply["verdicts"]]
        assert reply["class"] == "HISTORY" and statuses == ["edges", "alarm"], reply
        return "verdicts.jsonl holds both scans"

    def clean_exit():
        status = replies.get("daemon-exit", ("missing",))[0]
        assert status == "0", f"uwbd exit status {status} after SIGTERM"
        return "SIGTERM: exit 0"

    def board_state():
        with open(status_path, encoding="utf-8") as f:
            board = json.load(f)
        assert board["class"] == "STATUS", board
        lines = board["lines"]
        assert lines["trigger"] == 0 and lines["enable"] == 0, f"hardware not left safe: {lines}"
        assert board["steps_while_disabled"] == 0, f"{board['steps_while_disabled']} steps while disabled"
        wanted = 2 * positions * stack
        assert board["frames_sent"] >= wanted, f"{board['frames_sent']} frames sent, want >= {wanted}"
        return (f"{board['frames_sent']} frames over the UART, {board['steps_counted']} steps, "
                f"pulser idle, motor disabled")

    check.claim("daemon starts on the emulated board", daemon_up)
    check.claim("commissioning scan becomes the baseline", commissioning)
    check.claim("winding shifted on the emulated board", shift_requested)
    check.claim("shifted scan measures the shift within 0.5 mm", shifted)
    check.claim("history", history)
    check.claim("daemon stops cleanly", clean_exit)
    check.claim("emulated board saw a full, safe scan cycle", board_state)
    return check.failed


if __name__ == "__main__":
    sys.exit(main())
