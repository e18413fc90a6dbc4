#!/usr/bin/env python3
"""How much does a random tiling's luck matter? AUC against LTR over the tiling's seed.

A random tiling gives every display pixel's opening one of a few orientations, drawn from a
seed. The opening, and so the light the display lets through (LTR), is the same for every seed;
the arrangement, and so the PSF's halo and the MTF, is not. This script analyzes one design
under many seeds (and optionally several random tiling modes) and compares them with the
periodic tiling of the same opening:

- AUC, the area under the radially-minimum MTF from 0 to 0.5 cycles/pixel, averaged over
  the colour channels: higher is easier to deblur;
- LTR, the share of the light through the lens's pupil that the display passes: higher is
  less noise.

It prints one row per design and a summary, and with ``--out`` plots AUC against LTR and the
radially-minimum MTFs of the best and worst seeds beside the periodic tiling's.

    python3 design_study.py                          # l2inv-random, seeds 0..15
    python3 design_study.py --preset fourier-random --modes random-4 random-d4 --quick
    python3 design_study.py --seeds 32 --out study.png --jobs 2
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

import udc_studio as udc

RANDOM_MODES = ("random-4", "random-d4")


@dataclass
class Result:
    tiling: str
    seed: int | None  # None for the periodic tiling
    auc_cyc_per_px: np.ndarray  # per channel
    ltr: float
    freq_cyc_per_px: np.ndarray
    radial_min: np.ndarray  # mean over the channels

    @property
    def mean_auc_cyc_per_px(self) -> float:
        return float(self.auc_cyc_per_px.mean())

    @property
    def label(self) -> str:
        return "periodic" if self.seed is None else f"{self.tiling} seed {self.seed}"


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description="Sweep a random tiling's seed and compare AUC and LTR with the periodic "
        "tiling of the same opening.",
    )
    parser.add_argument("--preset", default="l2inv-random",
                        help="the design to study (default: %(default)s; see udc.presets())")
    parser.add_argument("--seeds", type=int, default=16, metavar="N",
                        help="seeds 0 to N-1 (default: %(default)s)")
    parser.add_argument("--modes", nargs="+", choices=RANDOM_MODES, metavar="MODE",
                        help="random tiling modes to sweep, from %(choices)s (default: the "
                        "preset's own mode, or random-4 when it is periodic)")
    parser.add_argument("--quick", action="store_true",
                        help="preview quality: faster, but its AUCs run higher than full "
                        "quality's, so compare only runs of the same quality")
    parser.add_argument("--jobs", type=int, default=1, metavar="N",
                        help="designs analyzed at once, in threads (default: %(default)s)")
    parser.add_argument("--out", metavar="FILE.png", help="write the plot to this PNG file")
    args = parser.parse_args(argv)
    if args.seeds < 1:
        parser.error("--seeds must be at least 1")
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    return args


def analyze(design: udc.Design, seed: int | None, quality: str) -> Result:
    a = udc.analyze(design, quality=quality)
    return Result(
        tiling=design.tiling,
        seed=seed,
        auc_cyc_per_px=a.auc,
        ltr=a.ltr,
        freq_cyc_per_px=a.freq_cyc_per_px,
        radial_min=a.radial_min.mean(axis=0),
    )


def print_table(results: list[Result], channels: list[str]) -> None:
    auc_columns = " ".join(f"{name:>7}" for name in channels)
    print(f"{'tiling':<10} {'seed':>5} {'AUC (cycles/pixel)':>19} {auc_columns} {'LTR (%)':>8}")
    for r in results:
        seed = "-" if r.seed is None else str(r.seed)
        per_channel = " ".join(f"{v:>7.4f}" for v in r.auc_cyc_per_px)
        print(f"{r.tiling:<10} {seed:>5} {r.mean_auc_cyc_per_px:>19.4f} {per_channel} "
              f"{100 * r.ltr:>8.2f}")


def print_summary(by_mode: dict[str, list[Result]], periodic: Result) -> None:
    print()
    print(f"AUC (cycles/pixel, mean over channels) against the periodic tiling's "
          f"{periodic.mean_auc_cyc_per_px:.4f}:")
    for mode, results in by_mode.items():
        aucs = np.array([r.mean_auc_cyc_per_px for r in results])
        best, worst = results[int(aucs.argmax())], results[int(aucs.argmin())]
        print(f"  {mode}: mean {aucs.mean():.4f} ± {aucs.std():.4f} over {len(aucs)} seeds, "
              f"best {best.mean_auc_cyc_per_px:.4f} (seed {best.seed}), "
              f"worst {worst.mean_auc_cyc_per_px:.4f} (seed {worst.seed}); "
              f"mean / periodic = {aucs.mean() / periodic.mean_auc_cyc_per_px:.2f}")
    ltrs = np.array([r.ltr for rs in by_mode.values() for r in rs])
    print(f"LTR: {100 * ltrs.min():.2f} to {100 * ltrs.max():.2f} % over the seeds, "
          f"{100 * periodic.ltr:.2f} % periodic")


def plot(by_mode: dict[str, list[Result]], periodic: Result, title: str, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_scatter, ax_mtf) = plt.subplots(1, 2, figsize=(13, 5))
    for (mode, results), color in zip(by_mode.items(), ("tab:purple", "tab:orange")):
        ax_scatter.scatter([100 * r.ltr for r in results],
                           [r.mean_auc_cyc_per_px for r in results],
                           color=color, label=f"{mode}, {len(results)} seeds")
        for r in results:
            ax_scatter.annotate(str(r.seed), (100 * r.ltr, r.mean_auc_cyc_per_px),
                                xytext=(3, 3), textcoords="offset points", fontsize="x-small")
        best = max(results, key=lambda r: r.mean_auc_cyc_per_px)
        worst = min(results, key=lambda r: r.mean_auc_cyc_per_px)
        ax_mtf.plot(best.freq_cyc_per_px, best.radial_min, color=color,
                    label=f"best: {best.label}, AUC {best.mean_auc_cyc_per_px:.3f}")
        ax_mtf.plot(worst.freq_cyc_per_px, worst.radial_min, color=color, ls=":",
                    label=f"worst: {worst.label}, AUC {worst.mean_auc_cyc_per_px:.3f}")
    ax_scatter.scatter([100 * periodic.ltr], [periodic.mean_auc_cyc_per_px], marker="*", s=200,
                       color="k", label="periodic")
    ax_scatter.set_xlabel("LTR (%)")
    ax_scatter.set_ylabel("AUC, mean over channels (cycles/pixel)")
    ax_scatter.set_title("Each point is one seed")
    ax_scatter.legend(fontsize="small")

    ax_mtf.plot(periodic.freq_cyc_per_px, periodic.radial_min, color="k", ls="--",
                label=f"periodic, AUC {periodic.mean_auc_cyc_per_px:.3f}")
    ax_mtf.set_xlim(0, 0.5)
    ax_mtf.set_ylim(0, 1.02)
    ax_mtf.set_xlabel("spatial frequency (cycles/pixel)")
    ax_mtf.set_ylabel("radially-minimum MTF, mean over channels")
    ax_mtf.set_title("Best and worst seeds against the periodic tiling")
    ax_mtf.legend(fontsize="small")

    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    quality = "preview" if args.quick else "full"
    try:
        base = udc.Design.from_preset(args.preset)
    except ValueError as e:
        print(f"design_study: {e}", file=sys.stderr)
        return 2
    modes = args.modes or [base.tiling if base.tiling in RANDOM_MODES else "random-4"]

    # The periodic tiling first, then every (mode, seed) pair.
    jobs = [(base.with_(tiling="repeat"), None)]
    jobs += [(base.with_(tiling=mode, seed=seed), seed)
             for mode in modes for seed in range(args.seeds)]
    print(f"{base!r}: {len(jobs)} analyses at {quality} quality\n")
    # Each analysis releases the GIL, so threads run them in parallel.
    # Ctrl-C reaches only the main thread: drop the queued analyses instead of waiting for them.
    pool = ThreadPoolExecutor(max_workers=args.jobs)
    try:
        results = list(pool.map(lambda job: analyze(*job, quality), jobs))
    except KeyboardInterrupt:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()

    periodic, randoms = results[0], results[1:]
    by_mode = {mode: [r for r in randoms if r.tiling == mode] for mode in modes}
    print_table(results, base.channels)
    print_summary(by_mode, periodic)

    if args.out:
        plot(by_mode, periodic, f"{base.name}: AUC against LTR over the random tiling's seed "
             f"({quality} quality)", args.out)
        print(f"\nwrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
