#!/usr/bin/env python3
"""The phase-mask V matrix (thesis chapter 4, conventions.md §7, thesis sampling convention) in numpy:
the same work as `udc_studio::core::phase::v_matrix`, written the way a numpy user would, to hold
the Rust implementation to its speed goal and to check that both agree.

Convention (conventions.md §7): lattice x = m·δ (δ = 15 nm); lenslets of round(pitch/δ) samples tile
from the first sample inside the display aperture D + 2 f_MLA tan 50°; each slit starts at sample
round_half_even((patternN − slitN)/2) of its cell; the grating is padded with ONES outside the
lenslets; input = rect(display aperture) · MLA 1; Fresnel TF over f_MLA on a grid wide enough not
to wrap (the thesis pads to M ≈ 10⁶ samples; any wrap-free grid gives the same field);
MLA 2 · rect(f/F#); Fraunhofer onto the M-point FFT's bins k·λf/(Mδ), M = 2⌊λf/(2δ·0.145)⌋,
k ∈ [−7168, 7168), summed in groups of 14 (pixel 512 starts on the axis).
Score = sum of |rfft| of the normalised 1024-pixel PSF over DC and 511 positive frequencies.

`--literal` runs one (λ0, λ) pair on the thesis's full M-sample grid instead, for checking the
wrap-free grid (slow: ~3 s per propagation).

`--no-padding` runs the Fresnel steps on the chain's own length (they then wrap), to measure
what a smaller grid would move.

Usage: python3 benches/phase_numpy.py [--pitch-um 42] [--fold 1] [--rows 30] [--preview]
       [--no-padding]
The last line printed is JSON: {"seconds", "propagations", "v", ...}.
"""
import argparse
import json
import math
import time

import numpy as np

D3_UM = 0.145
FINE = 14


def next_fast_size_235(m):
    v = max(m, 2)
    while True:
        r = v
        for p in (2, 3, 5):
            while r % p == 0:
                r //= p
        if r == 1 and v % 2 == 0:
            return v
        v += 1


class Chain:
    def __init__(self, pitch_um, fold, dx_um=0.015, fine=FINE, pad=True):
        self.pitch, self.fold, self.dx, self.fine = pitch_um, fold, dx_um, fine
        self.pad = pad
        self.d3 = D3_UM * FINE / fine
        self.n_index, self.f_mla = 1.515, pitch_um
        self.focal_um, self.pixels = 4670.0, 1024
        self.lens_w = self.focal_um / 2.0
        self.display_w = self.lens_w + 2 * self.f_mla * math.tan(math.radians(50.0))
        self.lenslets = max(1, math.ceil(self.display_w / pitch_um - 1e-9))
        self.pattern = round(pitch_um / dx_um)
        slit = round(pitch_um / (4.2 * dx_um))
        self.slit_start = int(np.round((self.pattern - slit) / 2))  # numpy rounds half to even
        self.slit = slit
        # The chain's samples: lattice points m_first … m_first + n − 1.
        self.m0 = math.ceil(-self.display_w / 2 / dx_um)
        while (self.m0 - 1) * dx_um >= -self.display_w / 2:
            self.m0 -= 1
        while self.m0 * dx_um < -self.display_w / 2:
            self.m0 += 1
        m_lo = min(self.m0, -math.ceil(self.lens_w / 2 / dx_um) - 1, -math.ceil(self.display_w / 2 / dx_um) - 1) - 1
        m_hi = max(self.m0 + self.lenslets * self.pattern, math.ceil(self.display_w / 2 / dx_um) + 1) + 1
        self.m = np.arange(m_lo, m_hi)
        self.n = len(self.m)
        x = self.m * dx_um
        self.display_rect = (np.abs(x) <= self.display_w / 2).astype(float)
        lens = np.abs(x) <= self.lens_w / 2
        idx = np.nonzero(lens)[0]
        self.start, self.end = idx[0], idx[-1] + 1
        rel = self.m - self.m0
        cell = rel // self.pattern
        self.q = rel - cell * self.pattern
        self.inside = (rel >= 0) & (cell < self.lenslets)
        self.slits = np.where(self.inside, ((self.q >= self.slit_start) & (self.q < self.slit_start + slit)).astype(float), 1.0)
        self.local = (self.q - self.pattern / 2) * dx_um
        self.kernels = {}

    def heights(self, lambda0_nm):
        sag = self.local ** 2 / (2 * (self.n_index - 1) * self.f_mla)
        d0 = self.fold * lambda0_nm * 1e-3 / (self.n_index - 1)
        return np.where(self.inside, np.mod(sag, d0), 0.0)

    def fresnel_len(self, lam_um):
        # The same wrap-free length as the Rust chain (the next 2·3·5-smooth even size), so both
        # solve the same discrete problem; `--literal` measures what the truncation costs.
        if not self.pad:
            return next_fast_size_235(self.n)
        return next_fast_size_235(math.ceil(self.n + lam_um * self.f_mla / self.dx ** 2))

    def czt_kernel(self, lam_um):
        if lam_um in self.kernels:
            return self.kernels[lam_um]
        lf = lam_um * self.focal_um
        big_m = 2 * math.floor(lf / (2 * self.dx * self.d3))
        du = lf / (big_m * self.dx)
        n_in, n_out = self.end - self.start, self.pixels * self.fine
        u0 = -(n_out // 2) * du
        size = 1 << math.ceil(math.log2(n_in + n_out - 1))
        beta = 2 * math.pi / lf
        alpha = beta * self.dx * du
        b = np.zeros(size, complex)
        mm = np.arange(n_out, dtype=float)
        b[:n_out] = np.exp(1j * np.mod(0.5 * alpha * mm * mm, 2 * math.pi))
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
        size_f = self.fresnel_len(lam)
        fx = np.fft.fftfreq(size_f, self.dx)
        transfer = np.exp(-1j * math.pi * lam * self.f_mla * fx ** 2)
        field = np.zeros(size_f, complex)
        field[: self.n] = plate * self.display_rect
        field = np.fft.ifft(np.fft.fft(field) * transfer)
        field[: self.n] *= self.slits
        field = np.fft.ifft(np.fft.fft(field) * transfer)
        lens = field[self.start:self.end] * plate[self.start:self.end]
        size, kernel, chirp, du = self.czt_kernel(lam)
        y = np.fft.ifft(np.fft.fft(lens * chirp, size) * kernel)
        intensity = np.abs(y[: self.pixels * self.fine]) ** 2
        scale = self.dx ** 2 / (lam * self.focal_um) * du / self.lens_w
        return intensity.reshape(self.pixels, self.fine).sum(axis=1) * scale

    def literal_psf(self, heights_um, wavelength_nm):
        """The thesis code's own grid: M samples at the display, an M-point FFT to the sensor."""
        lam = wavelength_nm * 1e-3
        k = 2 * math.pi / lam
        big_m = 2 * math.floor(lam * self.focal_um / (2 * self.dx * self.d3))
        plate = np.ones(big_m, complex)
        grating = np.ones(big_m)
        rect = np.zeros(big_m)
        at = self.m % big_m
        plate[at] = np.exp(-1j * k * (self.n_index - 1) * heights_um)
        grating[at] = self.slits
        rect[at] = self.display_rect
        lens = np.zeros(big_m)
        lens[at[self.start:self.end]] = 1.0
        fx = np.fft.fftfreq(big_m, self.dx)
        transfer = np.exp(-1j * math.pi * lam * self.f_mla * fx ** 2)
        field = np.fft.ifft(np.fft.fft(plate * rect) * transfer) * grating
        field = np.fft.ifft(np.fft.fft(field) * transfer) * plate * lens
        spectrum = np.fft.fft(field)
        ks = np.arange(-(self.pixels * self.fine) // 2, (self.pixels * self.fine) // 2) % big_m
        return (np.abs(spectrum[ks]) ** 2).reshape(self.pixels, self.fine).sum(axis=1)


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
    ap.add_argument("--literal", nargs=2, type=float, metavar=("LAMBDA0_NM", "LAMBDA_NM"))
    ap.add_argument("--no-padding", action="store_true",
                    help="Fresnel steps on the chain's own length (wraps; for comparison)")
    args = ap.parse_args()
    dx, fine = (0.06, 7) if args.preview else (0.015, 14)
    chain = Chain(args.pitch_um, args.fold, dx, fine, pad=not args.no_padding)
    if args.literal:
        l0, lam = args.literal
        h = chain.heights(l0)
        a, b = score(chain.psf(h, lam)), score(chain.literal_psf(h, lam))
        print(json.dumps({"wrap_free": a, "literal": b, "relative": abs(a - b) / b}))
        return
    grid = [401.0 + 10.0 * j for j in range(30)]
    start = time.perf_counter()
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
