#!/usr/bin/env python3
"""Pure-numpy reference of `analyze/iccp21/toled-repeat` (benches/analyze.rs, case a).

It does the same work as the Rust `analyze` of `Design::default_toled()` by the most direct
route, the dense formulation of conventions.md §0-4 written out without any of the Rust pruning
(full complex `fft2` of the whole padded pupil per channel). It serves two purposes:

* an independent check of the numbers: its AUCs must match the Rust ones to ~1e-6 relative;
* a speed baseline: benches/report.sh divides its median time by the Rust median.

Usage: numpy_reference.py [--open] [--runs N]
  --open    the open aperture (no display): the thesis check R 0.3068, G 0.3170, B 0.3274.
  --runs N  timed runs after one warm-up (default 5); the median is reported.

The last line printed is one JSON object (benches/report.sh reads it).
"""

import argparse
import json
import platform
import statistics
import sys
import time

import numpy as np

# The iccp21 recipe (conventions.md §4).
FOCAL_MM = 10.0
PUPIL_D_UM = 4000.0
DELTA1_UM = 8.0
CHANNELS = (("R", 610.0, 1524), ("G", 530.0, 1324), ("B", 470.0, 1174))
M_MAX = 1524
WINDOW_PX = 294
SAMPLES_PER_PX = 4
# The T-OLED pixel: 21x21 cells of 8 um (= delta1), a full-height slit at columns 8..12.
TILE_CELLS = 21
SLIT_COLS = range(8, 13)
EPSILON = 0.015
LOWEST_FRACTION = 0.3
THESIS_OPEN_AUC = {"R": 0.3068, "G": 0.3170, "B": 0.3274}


def aperture(open_aperture):
    """Effective aperture a = p * o on the M_MAX^2 pupil grid (axis at index M_MAX/2)."""
    offsets_um = (np.arange(M_MAX) - M_MAX // 2) * DELTA1_UM
    x = offsets_um[np.newaxis, :]
    y = offsets_um[:, np.newaxis]
    # Sample centres on or inside the rim count as inside, like the Rust rasteriser.
    pupil = (x * x + y * y <= (PUPIL_D_UM / 2) ** 2).astype(np.float64)
    if open_aperture:
        return pupil
    # Cells are exactly one sample, and the tiling starts at the array corner, so sample i sits
    # in cell i mod 21; the axis sample 762 = 36*21 + 6 lands on cell 6 as the recipe requires.
    cell = np.arange(M_MAX) % TILE_CELLS
    slit = np.isin(cell, list(SLIT_COLS)).astype(np.float64)
    return pupil * slit[np.newaxis, :]


def sensor_psf(a_full, m):
    """Sensor PSF (sums to 1) of one channel whose FFT size is m."""
    start = (M_MAX - m) // 2  # centre crop keeps the axis at index m/2
    a = a_full[start : start + m, start : start + m]
    fine = np.fft.fftshift(np.abs(np.fft.fft2(a)) ** 2)  # DC / axis at index m/2
    # Sensor pixel j holds the fine offsets 4(j-147) .. 4(j-147)+3 from the axis: the window
    # spans offsets -588 .. 587. Copy the grid into a zero window of 1176 fine samples so that
    # offsets the grid does not hold (the blue grid stops at -587 .. 586) count as zero.
    span = WINDOW_PX * SAMPLES_PER_PX
    lo = -(WINDOW_PX // 2) * SAMPLES_PER_PX  # first offset of the window
    win = np.zeros((span, span))
    first = max(lo, -(m // 2))
    last = min(lo + span, m // 2)  # exclusive
    src = slice(first + m // 2, last + m // 2)
    dst = slice(first - lo, last - lo)
    win[dst, dst] = fine[src, src]
    psf = win.reshape(WINDOW_PX, SAMPLES_PER_PX, WINDOW_PX, SAMPLES_PER_PX).sum(axis=(1, 3))
    return psf / psf.sum()


def ring_index(n):
    c = n // 2
    d = np.arange(n) - c
    # No ring distance is ever exactly k + 0.5 for integer offsets, so round-half-even (numpy)
    # and round-half-away (Rust) agree.
    return np.rint(np.hypot(d[:, np.newaxis], d[np.newaxis, :])).astype(np.int64)


def trapezoid(y, dx):
    return float(np.sum(0.5 * (y[1:] + y[:-1])) * dx)


def mtf_figures(psf, rings):
    n = psf.shape[0]
    otf = np.fft.fft2(psf)
    power = np.abs(otf) ** 2
    mtf = np.fft.fftshift(np.sqrt(power))
    half = n // 2
    keep = rings < half
    d = rings[keep]
    v = mtf[keep]
    rmin = np.full(half, np.inf)
    np.minimum.at(rmin, d, v)
    rmean = np.bincount(d, weights=v, minlength=half) / np.bincount(d, minlength=half)
    return trapezoid(rmin, 1.0 / n), trapezoid(rmean, 1.0 / n), power


def analyze(open_aperture):
    a = aperture(open_aperture)
    rings = ring_index(WINDOW_PX)
    out = {"auc_radial_min": {}, "auc_radial_mean": {}}
    h = []
    for name, _lam, m in CHANNELS:
        psf = sensor_psf(a, m)
        auc_min, auc_mean, power = mtf_figures(psf, rings)
        out["auc_radial_min"][name] = auc_min
        out["auc_radial_mean"][name] = auc_mean
        h.append((power / (power + EPSILON)).ravel())
    pooled = np.concatenate(h)
    k = max(int(np.floor(LOWEST_FRACTION * pooled.size)), 1)
    out["l_inv"] = -float(np.partition(pooled, k - 1)[:k].mean())
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--open", action="store_true", help="open aperture (no display)")
    ap.add_argument("--runs", type=int, default=5, help="timed runs after one warm-up")
    args = ap.parse_args()

    # Warm-up: numpy's pocketfft caches its plans too, so the timed runs compare like with like.
    result = analyze(args.open)
    times_ms = []
    for _ in range(max(args.runs, 1)):
        t0 = time.perf_counter()
        analyze(args.open)
        times_ms.append((time.perf_counter() - t0) * 1e3)

    design = "open-aperture" if args.open else "toled-repeat"
    for name, _lam, _m in CHANNELS:
        line = f"{name}: AUC(radial min) {result['auc_radial_min'][name]:.9f}"
        if args.open:
            want = THESIS_OPEN_AUC[name]
            rel = result["auc_radial_min"][name] / want - 1.0
            line += f"  thesis {want:.4f}  ({100 * rel:+.3f} %, tolerance ±0.3 %)"
        print(line)
    print(f"L_inv {result['l_inv']:.9f}")
    print(f"median {statistics.median(times_ms):.1f} ms over {len(times_ms)} runs")
    summary = {
        "design": design,
        "auc_radial_min": result["auc_radial_min"],
        "auc_radial_mean": result["auc_radial_mean"],
        "l_inv": result["l_inv"],
        "median_ms": statistics.median(times_ms),
        "runs_ms": times_ms,
        "numpy": np.__version__,
        "python": platform.python_version(),
    }
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
