#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into tests/fuzz/corpus/<name>/.

The seeds are committed; this script says where each came from and remakes
them after a format change:  python3 tests/fuzz/make-corpus.py [UWBSIM]
(UWBSIM defaults to build/uwbsim, which `make` builds). Seeds are small, so
that the fuzzer mutates inputs that look like the real thing: scans of a
few positions and samples made by the simulator, frames and sessions as
board/digitiser-protocol.md and board/emulated-gpio.md describe them, the
shipped configs, console lines.
"""
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
CORPUS = os.path.join(HERE, "corpus")


def write(target, name, data):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


# ---- uwbscan/1 ---------------------------------------------------------------

def simulate(uwbsim, *args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "seed.uwbscan")
        subprocess.run([uwbsim, "--seed", "7", *args, "-o", out], check=True)
        with open(out, "rb") as f:
            return f.read()


def split_scan(data):
    newline = data.index(b"\n")
    return json.loads(data[:newline]), data[newline + 1:]


def join_scan(header, payload, separators=(",", ":")):
    return json.dumps(header, separators=separators).encode() + b"\n" + payload


def scan_seeds(uwbsim):
    base = simulate(uwbsim, "--positions", "2", "--samples", "16", "--noise", "false")
    write("scan", "k2-s16.uwbscan", base)
    write("scan", "k1-s16.uwbscan",
          simulate(uwbsim, "--positions", "1", "--samples", "16", "--sample-interval-s", "5e-12", "--noise", "false"))
    write("scan", "k4-s64-noise-target.uwbscan",
          simulate(uwbsim, "--positions", "4", "--samples", "64", "--sample-interval-s", "8e-11",
                   "--t0-s", "2e-9", "--target-z-near-m", "0.2", "--target-z-far-m", "0.8",
                   "--scan-id", "seed-4", "--comment", "fuzz seed"))
    write("scan", "k3-s24-stack4.uwbscan",
          simulate(uwbsim, "--positions", "3", "--samples", "24", "--sample-interval-s", "2e-11",
                   "--stack", "4", "--first-position-m", "-0.05", "--noise", "false"))

    header, payload = split_scan(base)
    required = {k: header[k] for k in ("format", "positions", "samples", "sample_interval_s", "t0_s",
                                       "antenna_y_m", "tx_m", "rx_m")}
    write("scan", "header-required-only.uwbscan", join_scan(required, payload))
    write("scan", "header-spaced.uwbscan", join_scan(header, payload, separators=(", ", ": ")))
    extra = dict(header, created="2024-05-01T12:00:00Z", appliance={"serial": "UWB-0001", "fw": [1, 2]},
                 comment="caf\u00e9 \\ \"quoted\"")
    write("scan", "header-extra-keys.uwbscan", join_scan(extra, payload))
    write("scan", "header-crlf.uwbscan",
          json.dumps(header, separators=(",", ":")).encode() + b"\r\n" + payload)
    # Refused ones, each one step from a good file.
    write("scan", "bad-truncated.uwbscan", base[:-3])
    write("scan", "bad-trailing.uwbscan", base + b"\0\0\0\0")
    write("scan", "bad-nan-sample.uwbscan", join_scan(header, payload[:-4] + struct.pack("<f", float("nan"))))
    write("scan", "bad-duplicate-key.uwbscan",
          join_scan(header, payload).replace(b'"samples":16', b'"samples":16,"samples":16', 1))
    write("scan", "bad-no-newline.uwbscan", json.dumps(header).encode())


# ---- digitiser frames ------------------------------------------------------

SYNC = bytes([0xA5, 0x55, 0x57, 0x42])
PING, CONFIGURE, ARM, DISARM = 0x01, 0x02, 0x03, 0x04
PONG, CONFIGURED, ARMED, DISARMED, ERROR, DATA = 0x81, 0x82, 0x83, 0x84, 0x8F, 0x90


def frame(kind, sequence, payload=b""):
    header = SYNC + struct.pack("<BBHII", kind, 1, 0, sequence, len(payload))
    header += struct.pack("<I", zlib.crc32(header))
    body = header + payload
    return body + struct.pack("<I", zlib.crc32(body))


def configure_payload(samples, interval):
    return struct.pack("<Id", samples, interval)


def trace_payload(codes, volts_per_count=0.5 / 2048):
    return struct.pack("<If", len(codes), volts_per_count) + struct.pack("<%dh" % len(codes), *codes)


def pulse(samples, shift):
    return [int(3000 * (1 if (i + shift) % 7 < 3 else -1) * max(0, 8 - abs(i - 6 - shift)) / 8)
            for i in range(samples)]


def error_payload(code, text):
    return struct.pack("<H", code) + text.encode()


def frame_seeds():
    write("frame", "pong.bin", frame(PONG, 0, b"uwbemu 1.0 (emulated digitiser)"))
    write("frame", "configured.bin", frame(CONFIGURED, 1, configure_payload(2048, 1e-11)))
    write("frame", "armed-disarmed.bin", frame(ARMED, 2) + frame(DISARMED, 3))
    write("frame", "error.bin", frame(ERROR, 1, error_payload(3, "samples: 70000 is more than a frame carries")))
    write("frame", "data-16.bin", frame(DATA, 0, trace_payload(pulse(16, 0))))
    write("frame", "data-64-two.bin",
          frame(DATA, 5, trace_payload(pulse(64, 2))) + frame(DATA, 6, trace_payload(pulse(64, 3))))
    write("frame", "commands.bin",
          frame(PING, 0) + frame(CONFIGURE, 1, configure_payload(16, 1e-11)) + frame(ARM, 2) + frame(DISARM, 3))
    good = frame(DATA, 1, trace_payload(pulse(16, 1)))
    corrupt = bytearray(good)
    corrupt[30] ^= 0x40
    write("frame", "garbage-corrupt-truncated-good.bin",
          b"\x00noise\xa5\x55" + bytes(corrupt) + good[: len(good) // 2] + good)


def session(samples=16, interval=1e-11, data=()):
    """What a digitiser says to the client: PING, CONFIGURE and ARM replied
    (sequences 0, 1, 2), then the given DATA frames."""
    out = frame(PONG, 0, b"uwbemu 1.0 (emulated digitiser)")
    out += frame(CONFIGURED, 1, configure_payload(samples, interval))
    out += frame(ARMED, 2)
    for item in data:
        out += item
    return out


def data(sequence, samples=16, shift=0):
    return frame(DATA, sequence, trace_payload(pulse(samples, shift)))


def digitiser_seeds():
    write("digitiser", "three-traces.bin", session(data=[data(0), data(1, shift=1), data(2, shift=2)]))
    bad = bytearray(data(0))
    bad[40] ^= 1
    write("digitiser", "corrupt-then-retry.bin", session(data=[bytes(bad), data(1), data(2), data(3)]))
    write("digitiser", "stale-and-ahead.bin", session(data=[data(0), data(0), data(1), data(3)]))
    write("digitiser", "wrong-length.bin", session(data=[data(0, samples=15), data(1), data(2), data(3)]))
    write("digitiser", "truncated.bin", session(data=[data(0), data(1)[:30]]))
    write("digitiser", "configure-refused.bin",
          frame(PONG, 0, b"uwbemu 1.0") + frame(ERROR, 1, error_payload(2, "CONFIGURE payload must be 12 bytes")))
    write("digitiser", "configured-mismatch.bin", session(samples=32, data=[data(0)]))
    write("digitiser", "pong-unprintable.bin",
          frame(PONG, 0, b"dig\x01\xffitiser") + frame(CONFIGURED, 1, configure_payload(16, 1e-11)) +
          frame(ARMED, 2) + data(0))


# ---- daemon config -------------------------------------------------------------

def config_seeds():
    for board in ("emulated", "raspberry-pi-4"):
        with open(os.path.join(ROOT, "board", board, "uwbd.json"), "rb") as f:
            write("config", board + ".json", f.read())
    with open(os.path.join(ROOT, "board", "emulated", "uwbd.json")) as f:
        emulated = json.load(f)
    minimal = {
        "gpio": {"backend": "emulated", "endpoint": "unix:/run/uwbemu/gpio.sock"},
        "digitiser": {"endpoint": "tcp:192.0.2.10:4000", "samples": 1024, "sample_interval_ps": 20},
        "carriage": {"steps_per_mm": 80, "travel_mm": 500, "home_offset_mm": -10},
        "scan": {"positions": 11, "first_position_mm": 0, "step_mm": 40},
        "geometry": {"tx_mm": [-25, 0], "rx_mm": [25, 0], "eps_r": 2.2},
    }
    write("config", "minimal.json", json.dumps(minimal))
    console = json.loads(json.dumps(emulated))
    console["console"]["endpoint"] = "tcp:[::1]:2323"
    console["control"]["mode"] = "0600"
    console["geometry"]["target_z_mm"] = [150, 900]
    write("config", "console-tcp.json", json.dumps(console, indent=1))
    named = json.loads(json.dumps(emulated))
    named["gpio"] = {"backend": "libgpiod", "chip": "gpiochip0",
                     "lines": {"trigger": "GPIO17", "step": "GPIO27", "dir": 22, "enable": "GPIO23", "home": 24},
                     "home_active_low": False}
    write("config", "libgpiod-names.json", json.dumps(named))
    broken = json.loads(json.dumps(emulated))
    broken["digitiser"]["samples"] = "2048"
    write("config", "bad-type.json", json.dumps(broken))
    write("config", "bad-syntax.json", json.dumps(emulated)[:-40])


# ---- console / control commands ---------------------------------------------

def command_seeds():
    for name, text in {
        "status": "status\n", "scan": "scan\r\n", "verdict": "verdict\n", "help": "help\n",
        "history": "history\n", "history-n": "history 25\n", "baseline-set": "baseline set\n",
        "session": "status\n\nscan\nhistory 3\r\n  verdict \t\nbaseline set\nhelp\n",
        "refused": "history 0\nbaseline\nreboot now\nscan ../etc/passwd\n" + "x" * 70 + "\nstatus\n",
    }.items():
        write("command", name + ".txt", text)


# ---- emulated GPIO ---------------------------------------------------------------

LINES = ["trigger", "step", "dir", "enable", "home"]


def gpio_reply_transcript(home_after=None, crlf=False):
    """The board's answers to fuzz_gpio_reply.c's session (hello, then 24
    gets, the outputs set just before their get): home reads 1 from get
    number home_after on."""
    end = "\r\n" if crlf else "\n"
    out = ["ok uwb-gpio/1 uwbemu 1.0"]
    outputs = [0, 0, 0, 0]
    for i in range(24):
        line = 4 if i % 3 else (i // 3) % 5
        if line != 4:
            outputs[line] = i & 1
            value = outputs[line]
        else:
            value = 1 if home_after is not None and i >= home_after else 0
        out.append("val %s %d" % (LINES[line], value))
    return end.join(out) + end


def gpio_seeds():
    write("gpio_reply", "session.txt", gpio_reply_transcript())
    write("gpio_reply", "home-found.txt", gpio_reply_transcript(home_after=10))
    write("gpio_reply", "crlf.txt", gpio_reply_transcript(home_after=4, crlf=True))
    write("gpio_reply", "err-reply.txt", "ok uwb-gpio/1 uwbemu 1.0\nval trigger 0\nerr cannot set 'set home 1'\n")
    write("gpio_reply", "wrong-protocol.txt", "err protocol 'uwb-gpio/1' not spoken here; this is uwb-gpio/2\n")

    hello = "hello uwb-gpio/1\n"
    release = "set trigger 0\nset step 0\nset dir 0\nset enable 0\n"
    homing = "set enable 1\nset dir 0\n" + "set step 1\nset step 0\nget home\n" * 4
    steps_up = "set dir 1\n" + "set step 1\nset step 0\n" * 6 + "get home\n"
    fire = "set trigger 1\nset trigger 0\n"
    write("gpio_board", "connect.txt", hello + release)
    write("gpio_board", "home-and-scan.txt", hello + release + homing + steps_up + fire + steps_up + fire + release)
    write("gpio_board", "gets.txt", "".join("get %s\n" % name for name in LINES))
    write("gpio_board", "steps-disabled.txt", hello + "set enable 0\n" + "set step 1\nset step 0\n" * 3 + "get step\n")
    write("gpio_board", "refused.txt",
          "hello uwb-gpio/9\nset home 1\nset step 2\nget nothing\nreset\n\r\nset trigger 1 extra\n")


def main():
    uwbsim = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "uwbsim")
    scan_seeds(uwbsim)
    frame_seeds()
    digitiser_seeds()
    config_seeds()
    command_seeds()
    gpio_seeds()


if __name__ == "__main__":
    main()
