#!/usr/bin/env python3
"""Host end of a guest UART for tests/board/test_serial_link.c.

Connects to the unix socket of a qemu chardev (qemu is the server), and
answers every byte the guest sends with its bitwise inverse until qemu
closes the socket. Prints how many bytes crossed each way when it ends.

Usage: serial-peer.py SOCKET_PATH [CONNECT_TIMEOUT_S]
"""
import socket
import sys
import time


def connect(path, timeout_s):
    deadline = time.monotonic() + timeout_s
    while True:
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            sock.connect(path)
            return sock
        except OSError as error:
            sock.close()
            if time.monotonic() > deadline:
                sys.exit(f"serial-peer: cannot connect to {path}: {error.strerror}")
            time.sleep(0.05)


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    path = sys.argv[1]
    timeout_s = float(sys.argv[2]) if len(sys.argv) == 3 else 30.0
    inverse = bytes(255 - value for value in range(256))
    received = 0
    with connect(path, timeout_s) as sock:
        while True:
            try:
                chunk = sock.recv(65536)
            except ConnectionResetError:
                break
            if not chunk:
                break
            received += len(chunk)
            sock.sendall(chunk.translate(inverse))
    print(f"serial-peer: {received} bytes received and answered", file=sys.stderr)


if __name__ == "__main__":
    main()
