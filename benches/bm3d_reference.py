"""The reference BM3D's time on the denoise bench's inputs (the `bm3d` package by BM3D's
authors), for the speed ratio in docs/src/benchmarks.md. Same photos and σ as benches/denoise.rs (its noise
differs: numpy's generator, not ChaCha; the time does not depend on the draw).

usage: python3 benches/bm3d_reference.py   (prints one line per case: median of 3 runs;
       needs numpy, Pillow and bm3d: pip install bm3d pillow)
"""
import statistics
import time
from pathlib import Path

import numpy as np
from PIL import Image
import bm3d

SIGMA = 0.1
ROOT = Path(__file__).resolve().parent.parent / "assets" / "testset"


def main() -> None:
    rng = np.random.default_rng(1)
    for case, name in [("bm3d/grey-512", "camera.png"), ("cbm3d/rgb-512", "astronaut.png")]:
        clean = np.asarray(Image.open(ROOT / name), dtype=np.float64) / 255.0
        noisy = clean + SIGMA * rng.standard_normal(clean.shape)
        times = []
        for _ in range(3):
            start = time.perf_counter()
            if clean.ndim == 3:
                out = bm3d.bm3d_rgb(noisy, SIGMA)
            else:
                out = bm3d.bm3d(noisy, SIGMA)
            times.append(time.perf_counter() - start)
        psnr = 10 * np.log10(1.0 / np.mean((out - clean) ** 2))
        print(f"{case}: reference median {statistics.median(times):.2f} s, {psnr:.2f} dB")


if __name__ == "__main__":
    main()
