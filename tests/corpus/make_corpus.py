#!/usr/bin/env python3
"""Writes the malformed-input corpus next to this script (standard library only).

Every file here must be refused by the command that reads its kind, quickly, in one line, with no
file left behind and the input unchanged (tests/suite/corpus.rs). Run it again after adding a
case; the outputs are committed so the suite needs no Python.
"""
import json, os, struct, zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def put(kind, name, data):
    d = os.path.join(HERE, kind)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def chunk(tag, body):
    return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body))


def png(width, height, idat=b"", color=2):
    ihdr = struct.pack(">IIBBBBB", width, height, 8, color, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


good = json.load(open(os.path.join(ROOT, "presets", "toled-150dpi.json")))


def design(edit):
    d = json.loads(json.dumps(good))
    edit(d)
    return json.dumps(d)


def setp(path, value):
    def edit(d):
        o = d
        for k in path[:-1]:
            o = o[k]
        o[path[-1]] = value
    return edit


# Design files (analyze, export, restore, optimize).
put("design", "empty.json", b"")
put("design", "not-json.json", "this is not a design")
put("design", "truncated.json", json.dumps(good)[:200])
put("design", "binary.json", bytes(range(256)) * 8)
put("design", "deep-nesting.json", "[" * 20000 + "]" * 20000)
put("design", "wrong-version.json", design(setp(["version"], 99)))
put("design", "pitch-negative.json", design(setp(["opening", "pitch_um"], -168)))
put("design", "pitch-tiny.json", design(setp(["opening", "pitch_um"], 1e-300)))
put("design", "pitch-huge.json", design(setp(["opening", "pitch_um"], 1e308)))
put("design", "pitch-string.json", design(setp(["opening", "pitch_um"], "168")))
put("design", "fine-sample-tiny.json", design(setp(["optics", "fine_sample_um"], 1e-300)))
put("design", "focal-length-huge.json", design(setp(["optics", "focal_length_mm"], 1e308)))
put("design", "f-number-zero.json", design(setp(["optics", "f_number"], 0)))
put("design", "window-huge.json", design(setp(["optics", "window_px"], 10**12)))
put("design", "window-negative.json", design(setp(["optics", "window_px"], -5)))
put("design", "recipe-unknown.json", design(setp(["optics", "recipe"], "hubble")))
put("design", "unknown-field.json", design(setp(["optics", "zoom"], 3)))
put("design", "tiling-unknown.json", design(setp(["tiling", "mode"], "hexagonal")))
put("design", "cells-huge.json", design(setp(["opening", "cells"], ["#" * 600] * 600)))
put("design", "cells-ragged.json", design(setp(["opening", "cells"], ["##", "#"])))
put("design", "cells-empty.json", design(setp(["opening", "cells"], [])))
put("design", "wavelength-negative.json",
    design(setp(["channels"], [{"name": "G", "wavelengths_nm": [-530], "weights": [1]}])))
put("design", "wavelengths-many.json",
    design(setp(["channels"], [{"name": "G", "wavelengths_nm": [400 + 0.001 * k for k in range(2000)],
                                 "weights": [1] * 2000}])))
put("design", "weights-mismatch.json",
    design(setp(["channels"], [{"name": "G", "wavelengths_nm": [530], "weights": [1, 2]}])))
put("design", "no-channels.json", design(setp(["channels"], [])))

# Photos (restore --image, phase restore --photo) and opening patterns (analyze --pattern).
put("image", "bomb-30000.png", png(30000, 30000, zlib.compress(b"\0" * 90001 * 4)))
put("image", "bomb-65535x1.png", png(65535, 65535, zlib.compress(b"\0" * 1000)))
put("image", "zero-size.png", png(0, 0))
put("image", "truncated.png", open(os.path.join(ROOT, "assets", "photos", "astronaut_256.png"), "rb").read()[:3000])
put("image", "garbage.png", bytes((k * 37) % 256 for k in range(4096)))
put("image", "text.png", "not an image\n")
put("image", "empty.png", b"")
put("image", "bad-crc.png", png(4, 4, zlib.compress(b"\0" * 52))[:-8] + b"XXXXXXXX")

# HDR scenes (sensor --hdr).
exr = open(os.path.join(ROOT, "assets", "hdr", "StillLife_620x423.exr"), "rb").read()
put("hdr", "truncated.exr", exr[:60000])
put("hdr", "header-only.exr", exr[:400])
put("hdr", "garbage.exr", bytes((k * 91) % 256 for k in range(8192)))
put("hdr", "empty.exr", b"")
put("hdr", "huge.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n" + b"\0" * 64)
put("hdr", "truncated.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 64\n" + b"\x02\x02\x00\x40" * 8)
put("hdr", "png-named.exr", png(4, 4))

# Spectral responses (analyze --spectral).
put("spectral", "empty.csv", b"")
put("spectral", "header-only.csv", "wavelength_nm,r,g,b\n")
put("spectral", "words.csv", "wavelength_nm,r,g,b\nred,green,blue,x\n")
put("spectral", "nan.csv", "wavelength_nm,r,g,b\n400,NaN,0.1,0.1\n500,0.2,0.2,0.2\n")
put("spectral", "negative.csv", "wavelength_nm,r,g,b\n400,-1,0.1,0.1\n500,0.2,0.2,0.2\n")
put("spectral", "unsorted.csv", "wavelength_nm,r,g,b\n500,0.2,0.2,0.2\n400,0.1,0.1,0.1\n")
put("spectral", "huge-range.csv", "wavelength_nm,r,g,b\n1,0.2,0.2,0.2\n1e12,0.1,0.1,0.1\n")
put("spectral", "ragged.csv", "wavelength_nm,r,g,b\n400,0.1\n500,0.2,0.2,0.2\n")
put("spectral", "binary.csv", bytes(range(256)) * 4)

# Phase designs (phase export --design).
put("phase", "empty.json", b"")
put("phase", "not-json.json", "{")
put("phase", "wrong-kind.json", json.dumps(good))
put("phase", "binary.json", bytes(range(256)) * 8)

# Masks (the studio's mask import).
put("mask", "garbage.gds", bytes((k * 13) % 256 for k in range(2048)))
put("mask", "empty.gds", b"")
put("mask", "truncated.gds", b"\x00\x06\x00\x02\x02\x58\x00\x1c\x01\x02")
put("mask", "garbage.dxf", "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n90\n99999999\n")
put("mask", "text.dxf", "not a dxf at all\n")
