#!/usr/bin/env python3
"""Peak memory of `udc-studio restore` on camera-size photos (the Limits chapter's figures).

Writes a synthetic N x N 8-bit RGB PNG per size (smooth gradients under a fine pattern, so the
denoiser has texture to match), runs `restore` on it with the default design at 28 dB with the default
denoiser, writing every output image (`--out`), under `/usr/bin/time -v`, and prints the peak
resident set in MiB and in bytes per photo pixel. Usage:
benches/photo_memory.py [BINARY] [SIZE ...]; the default binary is target/release/udc-studio
and the default sizes 2048 and 4096.
"""
import os
import struct
import sys
import tempfile
import zlib

from peak_memory import measure

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
args = sys.argv[1:]
binary = args.pop(0) if args and not args[0].isdigit() else os.path.join(
    ROOT, "target/release/udc-studio")
sizes = [int(a) for a in args] or [2048, 4096]


def write_png(path, n):
    rows = []
    for y in range(n):
        row = bytearray([0])
        for x in range(n):
            fine = 40 if ((x // 3) + (y // 5)) % 2 else 0
            row += bytes(((x * 200 // n + fine) % 256, (y * 200 // n + fine) % 256,
                          ((x + y) * 100 // n + fine) % 256))
        rows.append(bytes(row))
    raw = zlib.compress(b"".join(rows), 6)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", raw))
        f.write(chunk(b"IEND", b""))


with tempfile.TemporaryDirectory() as tmp:
    for n in sizes:
        photo = os.path.join(tmp, f"photo{n}.png")
        write_png(photo, n)
        out = os.path.join(tmp, f"out{n}")
        peak_kb, wall = measure(
            [binary, "restore", "--image", photo, "--out", out, "--snr-db", "28",
             "--max-memory", "4G", "--json"])
        written = len(os.listdir(out))
        print(f"restore of a {n} x {n} photo: peak {peak_kb / 1024:.0f} MiB "
              f"({peak_kb * 1024 / (n * n):.0f} bytes per pixel), wall {wall}, "
              f"{written} images written")
