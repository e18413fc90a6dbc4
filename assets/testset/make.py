#!/usr/bin/env python3
"""Regenerates the denoising test set in this folder from scikit-image's bundled photos.

    python3 assets/testset/make.py

Each photo becomes a 512x512 8-bit PNG (RGB, or grey for grey sources): a centred 512x512
crop, or, for a photo smaller than 512 in a side, its largest centred square scaled up to 512
with Pillow's Lanczos filter. Only photos whose licence scikit-image states as public domain,
CC0 or "no known copyright restrictions" are used (see README.md here); `moon` and
`motorcycle_left` state none and are left out.

Needs scikit-image (only for the path of its data folder) and Pillow. Prints one line per file;
the README's table is written by hand from that output and the docstrings quoted there.
"""

from pathlib import Path

from PIL import Image
import skimage.data

SIDE = 512
HERE = Path(__file__).resolve().parent
DATA = Path(skimage.data.__file__).resolve().parent

# (output name, scikit-image file, keep grey): the scikit-image function each comes from and
# its licence sentence are in README.md.
PHOTOS = [
    ("astronaut.png", "astronaut.png", False),
    ("chelsea.png", "chelsea.png", False),
    ("coffee.png", "coffee.png", False),
    ("hubble_deep_field.png", "hubble_deep_field.jpg", False),
    ("ihc.png", "ihc.png", False),
    ("retina.png", "retina.jpg", False),
    ("rocket.png", "rocket.jpg", False),
    ("brick.png", "brick.png", True),
    ("camera.png", "camera.png", True),
    ("grass.png", "grass.png", True),
    ("gravel.png", "gravel.png", True),
]


def square_512(img):
    """The centred 512 crop, or the largest centred square scaled to 512 (and what was done)."""
    w, h = img.size
    side = min(w, h)
    if side >= SIDE:
        left, top = (w - SIDE) // 2, (h - SIDE) // 2
        crop = img.crop((left, top, left + SIDE, top + SIDE))
        if (w, h) == (SIDE, SIDE):
            return crop, "none (already 512x512)"
        return crop, f"centred 512x512 crop of {w}x{h} (offset x={left}, y={top})"
    left, top = (w - side) // 2, (h - side) // 2
    square = img.crop((left, top, left + side, top + side))
    scaled = square.resize((SIDE, SIDE), Image.Resampling.LANCZOS)
    return scaled, (
        f"centred {side}x{side} square of {w}x{h} (offset x={left}, y={top}), "
        f"scaled to 512x512 with Lanczos"
    )


def main():
    total = 0
    for out_name, source, grey in PHOTOS:
        img = Image.open(DATA / source)
        img = img.convert("L" if grey else "RGB")
        square, done = square_512(img)
        out = HERE / out_name
        square.save(out, optimize=True)
        size = out.stat().st_size
        total += size
        print(f"{out_name}: {source} -> {done}; {size // 1024} KiB")
    print(f"total {total / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
