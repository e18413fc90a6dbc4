"""The reference BM3D (the `bm3d` package by BM3D's authors: Mäkinen, Azzari, Foi) on a noisy
image the Rust test wrote, for the denoiser test to compare PSNRs.

usage: bm3d_check.py NOISY.f64 CLEAN.f64 HEIGHT WIDTH CHANNELS SIGMA2
Each file is raw little-endian float64, row-major, channels last. Prints one JSON object:
{"psnr_db": ..., "noisy_psnr_db": ..., "elapsed_s": ...}.
"""
import json
import sys
import time

import numpy as np
import bm3d


def main() -> None:
    noisy_path, clean_path, h, w, c, sigma2 = sys.argv[1:7]
    shape = (int(h), int(w), int(c))
    noisy = np.fromfile(noisy_path, dtype="<f8").reshape(shape)
    clean = np.fromfile(clean_path, dtype="<f8").reshape(shape)
    sigma = float(sigma2) ** 0.5
    start = time.perf_counter()
    if shape[2] == 3:
        out = bm3d.bm3d_rgb(noisy, sigma)
    else:
        out = bm3d.bm3d(noisy[:, :, 0], sigma)[:, :, None]
    elapsed = time.perf_counter() - start

    def psnr(a: np.ndarray) -> float:
        return float(10 * np.log10(1.0 / np.mean((a - clean) ** 2)))

    print(json.dumps({"psnr_db": psnr(out), "noisy_psnr_db": psnr(noisy), "elapsed_s": elapsed}))


if __name__ == "__main__":
    main()
