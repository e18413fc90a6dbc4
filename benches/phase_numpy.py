#!/usr/bin/env python3
"""The phase-mask V matrix (thesis chapter 4, PHYSICS.md §7) in numpy: the same work as
`udc_studio::core::phase::v_matrix`, written the way a numpy user would, to hold the Rust
implementation to its speed goal (>= 3x faster in one run) and to check that both agree.

Chain per (lambda0, lambda): plane wave . display rect -> MLA 1 -> Fresnel TF over f_MLA ->
display slits -> Fresnel TF -> MLA 2 . main-lens rect -> Fraunhofer by chirp-z onto the sensor
window (1024 pixels x 14 midpoint samples) -> box binning; score = sum of the one-sided MTF.

Usage: python3 benches/phase_numpy.py [--pitch-um 42] [--fold 1] [--rows 30] [--preview]
The last line printed is JSON: {"seconds", "propagations", "v", ...}.
"""
import argparse
import json
import math
import time

import numpy as np


def next_fast_size(m):
    v = max(m, 2)
    while True:
        r = v
        for p in (2, 3, 5, 7):
            while r % p == 0:
                r //= p
        if r == 1 and v % 2 == 0:
            return v
        v += 1


def coverage(x, dx, lo, hi):
    return np.clip(np.minimum(x + dx / 2, hi) - np.maximum(x - dx / 2, lo), 0.0, dx) / dx


class Chain:
    def __init__(self, pitch_um, fold, dx_um=0.015, fine=14):
        self.pitch, self.fold, self.dx, self.fine = pitch_um, fold, dx_um, fine
        self.n_index, self.f_mla, self.open_ratio = 1.515, pitch_um, 1.0 / 4.2
        self.focal_um, self.pixel_um, self.pixels = 4670.0, 2.0, 1024
        self.aperture = self.focal_um / 2.0
        display = self.aperture + 2 * self.f_mla * math.tan(math.radians(50.0))
        self.lenslets = max(1, math.ceil(display / pitch_um - 1e-9))
        span = max(self.lenslets * pitch_um, display) + 4 * max(pitch_um, 25.0)
        n = next_fast_size(math.ceil(span / dx_um))
        self.n = n
        x = (np.arange(n) - n // 2) * dx_um
        self.x = x
        self.display_rect = coverage(x, dx_um, -display / 2, display / 2)
        lens_rect = coverage(x, dx_um, -self.aperture / 2, self.aperture / 2)
        c0 = (0 - (self.lenslets - 1) / 2) * pitch_um
        local = np.mod(x - c0 + pitch_um / 2, pitch_um) - pitch_um / 2
        slit = self.open_ratio * pitch_um
        self.slits = coverage(local, dx_um, -slit / 2, slit / 2)
        nz = np.nonzero(lens_rect > 0)[0]
        self.start, self.end = nz[0], nz[-1] + 1
        self.lens_rect = lens_rect[self.start:self.end]
        rel = (x - c0) / pitch_um + 0.5
        l = np.floor(rel)
        self.inside = (l >= 0) & (l < self.lenslets)
        self.u = x - (c0 + l * pitch_um)
        self.fx = np.fft.fftfreq(n, dx_um)
        self.kernels = {}

    def heights(self, lambda0_nm):
        sag = self.u ** 2 / (2 * (self.n_index - 1) * self.f_mla)
        d0 = self.fold * lambda0_nm * 1e-3 / (self.n_index - 1)
        return np.where(self.inside, np.mod(sag, d0), 0.0)

    def czt_kernel(self, lam_um):
        if lam_um in self.kernels:
            return self.kernels[lam_um]
        n_in, n_out = self.end - self.start, self.pixels * self.fine
        size = next_fast_size(n_in + n_out - 1)
        du = self.pixel_um / self.fine
        beta = 2 * math.pi / (lam_um * self.focal_um)
        alpha = beta * self.dx * du
        u0 = (-(self.pixels // 2) - 0.5) * self.pixel_um + 0.5 * du
        b = np.zeros(size, complex)
        m = np.arange(n_out, dtype=float)
        b[:n_out] = np.exp(1j * np.mod(0.5 * alpha * m * m, 2 * math.pi))
        k = np.arange(1, n_in, dtype=float)
        b[size - np.arange(1, n_in)] = np.exp(1j * np.mod(0.5 * alpha * k * k, 2 * math.pi))
        nn = np.arange(n_in, dtype=float)
        chirp = np.exp(-1j * (np.mod(beta * self.dx * u0 * nn, 2 * math.pi)
                              + np.mod(0.5 * alpha * nn * nn, 2 * math.pi)))
        entry = (size, np.fft.fft(b), chirp, du)
        self.kernels[lam_um] = entry
        return entry

    def psf(self, heights_um, wavelength_nm):
        lam = wavelength_nm * 1e-3
        k = 2 * math.pi / lam
        plate = np.exp(-1j * k * (self.n_index - 1) * heights_um)
        transfer = np.exp(-1j * math.pi * lam * self.f_mla * self.fx ** 2)
        field = plate * self.display_rect
        field = np.fft.ifft(np.fft.fft(field) * transfer)
        field *= self.slits
        field = np.fft.ifft(np.fft.fft(field) * transfer)
        lens = field[self.start:self.end] * plate[self.start:self.end] * self.lens_rect
        size, kernel, chirp, du = self.czt_kernel(lam)
        y = np.fft.ifft(np.fft.fft(lens * chirp, size) * kernel)
        intensity = np.abs(y[: self.pixels * self.fine]) ** 2
        scale = self.dx ** 2 / (lam * self.focal_um) * du / self.aperture
        return intensity.reshape(self.pixels, self.fine).sum(axis=1) * scale


def score(psf):
    s = psf.sum()
    if not s > 0:
        return 0.0
    return float(np.abs(np.fft.rfft(psf / s))[: len(psf) // 2].sum())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pitch-um", type=float, default=42.0)
    ap.add_argument("--fold", type=float, default=1.0)
    ap.add_argument("--rows", type=int, default=30, help="rows of V (lambda0 values) to compute")
    ap.add_argument("--preview", action="store_true")
    args = ap.parse_args()
    dx, fine = (0.06, 7) if args.preview else (0.015, 14)
    grid = [401.0 + 10.0 * j for j in range(30)]
    start = time.perf_counter()
    chain = Chain(args.pitch_um, args.fold, dx, fine)
    v = []
    for l0 in grid[: args.rows]:
        h = chain.heights(l0)
        v.append([score(chain.psf(h, lam)) for lam in grid])
    seconds = time.perf_counter() - start
    props = len(v) * len(grid)
    print(f"numpy V: {props} propagations in {seconds:.1f} s ({1000 * seconds / props:.1f} ms each), "
          f"{chain.n} display samples, {chain.lenslets} lenslets")
    print(json.dumps({"seconds": seconds, "propagations": props, "samples": chain.n,
                      "lenslets": chain.lenslets, "numpy": np.__version__, "v": v}))


if __name__ == "__main__":
    main()
