#!/usr/bin/env python3
"""Writes the design files and patterns that `udc-studio reproduce` runs (presets/reproduce/).

    python3 presets/reproduce/designs/make.py      # from the repository; Python 3 and Pillow

Why they exist. The pupil grid of a design samples its cells: with the sample spacing
`pupil_sample_um` (δ1) equal to the cell, each sample is one cell; with δ1 larger than the cell
the cells are under-sampled (the opening blurs away), and with δ1 a fraction of the cell the
studio's area-weighted rasterisation loses light on every cell edge (measured: L2 + inv's LTR
0.227 at δ1 = cell, 0.183 at δ1 = cell / 2). `--pitch-um` alone keeps the preset's δ1, so a sweep
over pitch needs a design per pitch whose δ1 is its cell:

- `fig3.9/base-<dpi>dpi.json`: the iccp21 camera with δ1 = pitch / 84, two pupil samples per
  cell, and the tile origin a quarter cell past where the presets put it (12.25 of 42 cells), so
  that every cell edge falls on a sample edge and no light is lost to partly covered samples;
  the PSF window is the whole FFT grid at 470 nm (λf/δ1 in 2-µm pixels), so that a capture keeps
  at least 97 % of the light every layout scatters (conventions.md §5: with one sample per cell
  and the 294-pixel window a P-OLED at 300 DPI kept 45 %). Every opening of Fig. 3.9 is a 42×42
  pattern (`../patterns/*-42.png`: the 21×21 openings upsampled 2×, P-OLED's own 42×42), so one
  base design per DPI serves them all through `--pattern`;
- `ch4-*-600dpi.json`: Table 4.1's 2-D layouts at 600 DPI with the chapter-4 camera
  (f = 4.67 mm, F/2, 2 µm pixels), δ1 = 1 µm = the cell.
"""

import json
import math
from pathlib import Path

from PIL import Image

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
PATTERNS = HERE.parent / "patterns"

# Fig. 3.9: 80 … 300 DPI.
FIG_3_9_DPI = [80, 100, 150, 200, 300]


def preset(name):
    return json.loads((ROOT / "presets" / f"{name}.json").read_text())


def cells_of(design):
    """The opening as rows of 0/1 (or amplitude) floats."""
    rows = design["opening"]["cells"]
    return [[1.0 if c == "#" else 0.0 for c in r] if isinstance(r, str) else list(r) for r in rows]


def upsample(cells, k):
    return [[v for v in row for _ in range(k)] for row in cells for _ in range(k)]


def text_rows(cells):
    """Binary rows as the design files write them (`#` open, `.` closed)."""
    return ["".join("#" if v == 1.0 else "." for v in row) for row in cells]


def write_json(path, design, compact_numbers=False):
    path.parent.mkdir(parents=True, exist_ok=True)
    if compact_numbers:
        rows = design["opening"]["cells"]
        design = dict(design, opening=dict(design["opening"], cells="@@CELLS@@"))
        text = json.dumps(design, indent=2, ensure_ascii=False)
        cells = "[\n" + ",\n".join("      " + json.dumps(r) for r in rows) + "\n    ]"
        text = text.replace('"@@CELLS@@"', cells)
    else:
        text = json.dumps(design, indent=2, ensure_ascii=False)
    path.write_text(text + "\n")


def write_png(path, cells):
    n = len(cells)
    img = Image.new("L", (n, n))
    img.putdata([255 if v >= 0.5 else 0 for row in cells for v in row])
    path.parent.mkdir(parents=True, exist_ok=True)
    img.save(path)


def iccp21(delta1, window_px=294):
    return {
        "recipe": "custom",
        "focal_length_mm": 10.0,
        "f_number": 2.5,
        "pupil_sample_um": delta1,
        "fine_sample_um": 0.5,
        "sensor_pixel_um": 2.0,
        "window_px": window_px,
        "axis_in_pixel_um": [0.25, 0.25],
    }


# Fig. 3.9's pupil samples per cell, and the shortest wavelength (nm) whose FFT grid the window
# fills.
FIG_3_9_SAMPLES_PER_CELL = 2
FIG_3_9_SHORTEST_NM = 470.0


def chapter4(delta1):
    return {
        "recipe": "custom",
        "focal_length_mm": 4.67,
        "f_number": 2.0,
        "pupil_sample_um": delta1,
        "fine_sample_um": 0.4,
        "sensor_pixel_um": 2.0,
        "window_px": 512,
        "axis_in_pixel_um": [0.2, 0.2],
    }


def fig3_9():
    patterns = {
        "toled": ("toled-150dpi", 2),
        "poled": ("poled-336um", 1),
        "l2-repeat": ("l2-repeat", 2),
        "l2-random": ("l2-random", 2),
        "l2inv-repeat": ("l2inv-repeat", 2),
        "l2inv-random": ("l2inv-random", 2),
    }
    for name, (source, k) in patterns.items():
        write_png(PATTERNS / f"{name}-42.png", upsample(cells_of(preset(source)), k))
    base = preset("toled-150dpi")
    for dpi in FIG_3_9_DPI:
        pitch = round(25400.0 / dpi, 4)
        delta1 = round(pitch / (42 * FIG_3_9_SAMPLES_PER_CELL), 6)
        # The grid at the shortest wavelength spans λf/δ1 on the sensor: 2-µm pixels, even.
        grid_px = FIG_3_9_SHORTEST_NM * 1e-3 * 10_000.0 / delta1 / 2.0
        window = 2 * round(grid_px / 2)
        d = {
            "format": base["format"],
            "version": base["version"],
            "name": f"Fig. 3.9 base, {dpi} DPI",
            "description": (
                f"The base of Fig. 3.9's {dpi}-DPI points: pitch {pitch} µm in 42×42 cells of "
                f"{2 * delta1:.4g} µm, sampled two pupil samples per cell (δ1 = {delta1:.4g} µm) "
                "with the tile origin on a sample edge, so that neither under-sampling nor "
                "partly covered samples change the opening; the iccp21 camera (f = 10 mm, "
                f"f/2.5, 2 µm pixels) with a {window}-pixel window, the whole FFT grid at 470 nm, "
                "so that a capture keeps at least 97 % of the light of every layout. Its opening "
                "(the T-OLED slit, upsampled 2×) is replaced by each layout's 42×42 pattern "
                "(`--pattern`); written by designs/make.py"
            ),
            "opening": {"pitch_um": pitch, "cells": text_rows(upsample(cells_of(base), 2))},
            "tiling": {
                "mode": "repeat",
                "seed": 0,
                "origin_offset_cells": [12.25, 12.25],
                "wiring_gap_um": 0.0,
            },
            "optics": iccp21(delta1, window),
            "channels": base["channels"],
        }
        write_json(HERE / "fig3.9" / f"base-{dpi}dpi.json", d)


CAMERA = (
    "the chapter-4 camera of thesis §4.5 (f = 4.67 mm, F/2: a 2.335 mm pupil; 2 µm pixels, as "
    "the phase model's), sampled at δ2 = 0.4 µm (5 samples per pixel; zero-padding 2.35× at "
    "470 nm) on a 512-pixel (1 mm) window, half the phase model's 1024-pixel sensor; light "
    "scattered beyond the window is dropped and the PSF renormalised, as for every display PSF "
    "of the studio. δ1 = 1 µm: one pupil sample per cell"
)


def chapter4_designs():
    # T-OLED: the 5-of-21 slit upsampled to 42 cells of 1 µm.
    t = preset("toled-600dpi")
    toled = {
        "format": t["format"],
        "version": t["version"],
        "name": "T-OLED 600 DPI, chapter-4 camera",
        "description": (
            "T-OLED at 600 DPI (the 5-of-21 slit as 10 of 42 cells of 1 µm, 42 µm pitch, LTR "
            f"23.8 %) seen through {CAMERA}. The 2-D counterpart of `phase restore --bare`, a "
            "cross-check of the 1-D phase model in `reproduce table4.1`; written by make.py"
        ),
        "opening": {"pitch_um": 42.0, "cells": text_rows(upsample(cells_of(t), 2))},
        "tiling": dict(t["tiling"], origin_offset_cells=[12.0, 12.0]),
        "optics": chapter4(1.0),
        "channels": t["channels"],
    }
    write_json(HERE / "ch4-toled-600dpi.json", toled)
    y = preset("l2inv-random")
    yang = {
        "format": y["format"],
        "version": y["version"],
        "name": "Yang et al. (L2 + inv, random) 600 DPI, chapter-4 camera",
        "description": (
            "The chapter-3 optimized random layout (top-10 L2 + inv opening, random-4 tiling "
            "seed 0, preset l2inv-random, open 22.7 %) at 600 DPI (42 cells of 1 µm: its 21 "
            f"cells upsampled 2×) seen through {CAMERA}. The \"Yang et al.\" row of thesis "
            "Table 4.1 (LTR 22.6 %), for `reproduce table4.1`; written by make.py"
        ),
        "opening": {"pitch_um": 42.0, "cells": text_rows(upsample(cells_of(y), 2))},
        "tiling": dict(y["tiling"], origin_offset_cells=[12.0, 12.0]),
        "optics": chapter4(1.0),
        "channels": y["channels"],
    }
    write_json(HERE / "ch4-yang-600dpi.json", yang)
    p = preset("poled-336um")
    cells = cells_of(p)
    open_fraction = sum(map(sum, cells)) / sum(map(len, cells))
    # P-OLED's 8.3 % (Table 4.1) is its polyimide substrate: an amplitude transmittance on
    # the openings, LTR = amplitude² × open fraction.
    amplitude = round(math.sqrt(0.083 / open_fraction), 4)
    poled = {
        "format": p["format"],
        "version": p["version"],
        "name": "P-OLED 600 DPI (8.3 % LTR), chapter-4 camera",
        "description": (
            f"P-OLED openings (preset poled-336um, open {100 * open_fraction:.1f} %) at 600 DPI "
            f"(42 cells of 1 µm) with an amplitude transmittance of {amplitude} in every "
            "opening, standing for the polyimide substrate thesis §4.5 blames for P-OLED's low "
            f"throughput: LTR {amplitude}² × {open_fraction:.4f} = 8.3 % (Table 4.1), without "
            f"its colour shift; seen through {CAMERA}. The \"POLED\" row of Table 4.1, for "
            "`reproduce table4.1`; written by make.py"
        ),
        "opening": {
            "pitch_um": 42.0,
            "cells": [[amplitude if v == 1.0 else 0.0 for v in row] for row in cells],
        },
        "tiling": p["tiling"],
        "optics": chapter4(1.0),
        "channels": p["channels"],
    }
    write_json(HERE / "ch4-poled-600dpi.json", poled, compact_numbers=True)


if __name__ == "__main__":
    fig3_9()
    chapter4_designs()
