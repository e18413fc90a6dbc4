"""The reference BM3D (the `bm3d` package by BM3D's authors: Mäkinen, Azzari, Foi) on a noisy
image the Rust test wrote, for the denoiser test to compare PSNRs.

usage: bm3d_check.py CLEAN.f64 HEIGHT WIDTH CHANNELS NOISY.f64 SIGMA2 [NOISY.f64 SIGMA2 ...]
Each file is raw little-endian float64, row-major, channels last. Prints one JSON object per
noisy image, one a line: {"psnr_db": ..., "noisy_psnr_db": ..., "elapsed_s": ...}. The images
share one process because importing the package takes longer than denoising a small crop.
"""
import json
import sys
import time

import numpy as np
import bm3d


def main() -> None:
    clean_path, h, w, c = sys.argv[1:5]
    pairs = sys.argv[5:]
    if not pairs or len(pairs) % 2:
        sys.exit("give NOISY.f64 SIGMA2 pairs after CHANNELS")
    shape = (int(h), int(w), int(c))
    clean = np.fromfile(clean_path, dtype="<f8").reshape(shape)

    def psnr(a: np.ndarray) -> float:
        return float(10 * np.log10(1.0 / np.mean((a - clean) ** 2)))

    for noisy_path, sigma2 in zip(pairs[::2], pairs[1::2]):
        noisy = np.fromfile(noisy_path, dtype="<f8").reshape(shape)
        sigma = float(sigma2) ** 0.5
        start = time.perf_counter()
        if shape[2] == 3:
            out = bm3d.bm3d_rgb(noisy, sigma)
        else:
            out = bm3d.bm3d(noisy[:, :, 0], sigma)[:, :, None]
        elapsed = time.perf_counter() - start
        print(json.dumps({"psnr_db": psnr(out), "noisy_psnr_db": psnr(noisy), "elapsed_s": elapsed}))


if __name__ == "__main__":
    main()
