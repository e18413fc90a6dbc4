#!/usr/bin/env python3
"""Peak memory of `udc-studio sensor` on camera-size HDR scenes (the Limits chapter's figures).

Writes a synthetic N x N Radiance .hdr per size (a dark-to-bright ramp over five decades under a
fine pattern, so the gain and bin maps vary), runs `sensor --hdr` on it with Table 5.4's four
strategies, writing every output image (`--out`), under `/usr/bin/time -v`, and prints the peak
resident set in MiB and in bytes per scene pixel. Usage:
benches/sensor_memory.py [BINARY] [--cfa rggb] [SIZE ...]; the default binary is
target/release/udc-studio and the default sizes 2048 and 4096.
"""
import math
import os
import sys
import tempfile

from peak_memory import measure

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
args = sys.argv[1:]
binary = args.pop(0) if args and not args[0].isdigit() and not args[0].startswith("--") \
    else os.path.join(ROOT, "target/release/udc-studio")
extra = []
if "--cfa" in args:
    i = args.index("--cfa")
    extra = ["--cfa", args[i + 1]]
    del args[i:i + 2]
sizes = [int(a) for a in args] or [2048, 4096]


def rgbe(r, g, b):
    """One pixel in Radiance's shared-exponent encoding."""
    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes((int(r * scale), int(g * scale), int(b * scale), exponent + 128))


def write_hdr(path, n):
    # Green changes in 64 steps down the image; each distinct row is built once.
    rows = {}
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {n} +X {n}\n".encode())
        for y in range(n):
            key = ((y // 5) % 2, y * 64 // n)
            if key not in rows:
                fine = 1.0 + 0.3 * (key[0] * 2 - 1)
                green = 0.5 + key[1] / 128
                row = bytearray()
                for x in range(n):
                    level = 10.0 ** (5.0 * x / n - 3.0) * fine * (1.2 if (x // 3) % 2 else 0.8)
                    row += rgbe(level, level * green, level * 0.7)
                rows[key] = bytes(row)
            f.write(rows[key])


with tempfile.TemporaryDirectory() as tmp:
    for n in sizes:
        scene = os.path.join(tmp, f"scene{n}.hdr")
        write_hdr(scene, n)
        out = os.path.join(tmp, f"out{n}")
        peak_kb, wall = measure(
            [binary, "sensor", "--hdr", scene, "--out", out, "--max-memory", "8G", "--json",
             *extra])
        written = len(os.listdir(out))
        print(f"sensor{' ' + ' '.join(extra) if extra else ''} on a {n} x {n} scene: "
              f"peak {peak_kb / 1024:.0f} MiB ({peak_kb * 1024 / (n * n):.0f} bytes per pixel), "
              f"wall {wall}, {written} images written")
