#!/usr/bin/env python3
"""The display-layout analysis on the CPU and on the GPU, in the same run.

For the T-OLED at 150, 300 and 600 DPI (the presets `toled-150dpi`, `toled-300dpi`,
`toled-600dpi`, the thesis's iccp21 recipe at full quality), prints the adapter, then per design:
  first  the first call in this process (the GPU's includes opening the device and compiling the
         kernels; the CPU's its FFT plans);
  warm   the median of the next N calls;
each as the call's time inside Rust (`Analysis.call_ms`, advice off), and the GPU's largest
difference from the CPU's PSF (as a fraction of its peak) and AUC.

Then one phase operator: a λ0 plan's restoration (`phase restore --lambda0 uniform --relay
wrapped-display --peaks --denoise none`, the thesis's sampling) whose operator's propagations (one
per scene column and wavelength through the double MLA on the wrapped grid) run on either
backend: first a 256-column scene, then ("warm", device open, a fresh operator) 255 columns (`--phase-columns`); the
wall time of the whole job (the operator dominates; the CG solve is the same on both), with the
differences of the LTR and PSNR as the job reports them (rounded: the LTR to 1e-5, the PSNR to
1e-6 dB).

Then V (`phase invertibility --relay wrapped-display`: 900 propagations, each its own plate and
wavelength, one direction per call to the device), once per backend, with the largest relative
difference of its entries and the transforms the device counted.

Then the opening optimizer (`udc-studio optimize`, the command-line binary: the display optimizer
has no Python entry point) on each design for `--optimize-epochs` epochs per backend: the run's
time per epoch (`elapsed_ms`, which includes scoring the start and the result) and the first
epoch's `L_inv` difference.

Usage: python3 benches/gpu.py [--runs N] [--backend gpu|auto] [--designs A,B] [--phase-columns N]
                              [--v-preview] [--optimize-epochs N]
  (--designs, --phase-columns, --v-preview and --optimize-epochs shrink the run, e.g. to check
   the script on a software driver: --runs 1 --designs fourier-square --phase-columns 16
   --v-preview --optimize-epochs 1)
  one command on a machine with a GPU and a Vulkan, Metal or DX12 driver:
      cargo build --release -p udc-studio-python -p udc-studio && \\
      UDC_NATIVE_LIB=target/release/lib_native.so python3 benches/gpu.py
  (without UDC_NATIVE_LIB the package is staged from target/debug as the Python tests do; the
   optimizer rows run target/release/udc-studio, else target/debug/udc-studio, else $UDC_CLI).
The last line printed is one JSON object.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from python_peers import import_udc_studio  # noqa: E402  (the same staging)

DESIGNS = ["toled-150dpi", "toled-300dpi", "toled-600dpi"]


def timings(udc, name: str, backend: str, runs: int):
    first = udc.analyze(name, advice="none", backend=backend)
    warm = [udc.analyze(name, advice="none", backend=backend).call_ms for _ in range(runs)]
    return first, statistics.median(warm)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--backend", choices=["gpu", "auto"], default="gpu")
    parser.add_argument("--designs", default=",".join(DESIGNS),
                        help="comma-separated presets (default: the three T-OLEDs)")
    parser.add_argument("--phase-columns", type=int, default=256,
                        help="the phase operator's scene columns (default 256)")
    parser.add_argument("--v-preview", action="store_true",
                        help="V at the preview sampling (default: the thesis's)")
    parser.add_argument("--optimize-epochs", type=int, default=10,
                        help="epochs of each optimizer run (default 10)")
    args = parser.parse_args()
    udc, how = import_udc_studio()
    print(f"udc_studio: {how}")
    rows = []
    adapter = None
    for name in args.designs.split(","):
        cpu_first, cpu_warm = timings(udc, name, "cpu", args.runs)
        with warnings.catch_warnings(record=True) as notes:
            warnings.simplefilter("always")
            try:
                gpu_first, gpu_warm = timings(udc, name, args.backend, args.runs)
            except ValueError as e:
                sys.exit(f"no GPU to time: {e}")
        for n in notes:
            print(f"  {n.message}")
        adapter = gpu_first.adapter or "the CPU (auto fell back)"
        psf_diff = float(np.max(np.abs(gpu_first.psf - cpu_first.psf)) / cpu_first.psf.max())
        auc_diff = float(np.max(np.abs(gpu_first.auc / cpu_first.auc - 1)))
        row = {
            "design": name,
            "cpu_first_ms": cpu_first.call_ms,
            "cpu_warm_ms": cpu_warm,
            "gpu_first_ms": gpu_first.call_ms,
            "gpu_warm_ms": gpu_warm,
            "psf_max_diff_of_peak": psf_diff,
            "auc_max_rel_diff": auc_diff,
        }
        rows.append(row)
    print(f"adapter: {adapter}")
    print(f"{'design':<14} {'CPU first':>10} {'CPU warm':>10} {'GPU first':>10} {'GPU warm':>10}"
          f" {'PSF diff':>9} {'AUC diff':>9}")
    for r in rows:
        print(f"{r['design']:<14} {r['cpu_first_ms']:>8.0f}ms {r['cpu_warm_ms']:>8.0f}ms "
              f"{r['gpu_first_ms']:>8.0f}ms {r['gpu_warm_ms']:>8.0f}ms "
              f"{r['psf_max_diff_of_peak']:>9.1e} {r['auc_max_rel_diff']:>9.1e}")
    phase = phase_rows(udc, args.backend, args.phase_columns)
    print(f"{'phase operator':<14} {'CPU first':>10} {'CPU warm':>10} {'GPU first':>10}"
          f" {'GPU warm':>10}"
          f" {'LTR diff':>9} {'PSNR diff':>9}")
    label = f"λ0 plan {args.phase_columns}"
    print(f"{label:<14} {phase['cpu_first_ms']:>8.0f}ms {phase['cpu_warm_ms']:>8.0f}ms "
          f"{phase['gpu_first_ms']:>8.0f}ms {phase['gpu_warm_ms']:>8.0f}ms "
          f"{phase['ltr_rel_diff']:>9.1e} {phase['psnr_diff_db']:>7.3f}dB")
    v = v_row(udc, args.backend, args.v_preview)
    print(f"{'V matrix':<14} {'CPU':>10} {'GPU':>10} {'V diff':>9} {'on device':>10}")
    label = "wrapped 900"
    print(f"{label:<14} {v['cpu_ms']:>8.0f}ms {v['gpu_ms']:>8.0f}ms "
          f"{v['v_max_rel_diff']:>9.1e} {v['device_transforms']:>10}")
    opt = optimize_rows(args.designs.split(","), args.backend, args.optimize_epochs)
    if opt:
        print(f"{'optimizer':<14} {'CPU/epoch':>10} {'GPU/epoch':>10} {'L_inv diff':>11}")
        for r in opt:
            print(f"{r['design']:<14} {r['cpu_ms_per_epoch']:>8.0f}ms "
                  f"{r['gpu_ms_per_epoch']:>8.0f}ms {r['loss_inv_rel_diff']:>11.1e}")
    print(json.dumps({"adapter": adapter, "runs": args.runs, "rows": rows, "phase": phase,
                      "v": v, "optimize": opt}))


def cli_binary():
    for path in [os.environ.get("UDC_CLI"), REPO / "target/release/udc-studio",
                 REPO / "target/debug/udc-studio"]:
        if path and Path(path).is_file():
            return str(path)
    return None


def optimize_rows(designs, backend: str, epochs: int):
    cli = cli_binary()
    if cli is None:
        print("optimizer: skipped, no udc-studio binary (build it: cargo build --release -p "
              "udc-studio, or set UDC_CLI)")
        return []
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in designs:
            def run(b: str):
                out = subprocess.run(
                    [cli, "optimize", "--preset", name, "--epochs", str(epochs), "--json",
                     "--backend", b, "--out", str(Path(tmp) / f"{name}-{b}.json")],
                    check=True, capture_output=True, text=True)
                return json.loads(out.stdout)
            cpu, gpu = run("cpu"), run(backend)
            first = [r["history"][0]["loss_inv"] for r in (cpu, gpu)]
            rows.append({
                "design": name,
                "epochs": epochs,
                "cpu_ms_per_epoch": cpu["elapsed_ms"] / epochs,
                "gpu_ms_per_epoch": gpu["elapsed_ms"] / epochs,
                "loss_inv_rel_diff": abs(first[1] / first[0] - 1),
                "device_transforms": gpu.get("backend", {}).get("device_transforms", 0),
            })
    return rows


def phase_restore(udc, backend: str, columns: int):
    start = time.perf_counter()
    out = udc.phase.restore(lambda0="uniform", relay="wrapped-display", peaks=True,
                            denoise="none", photons=[1000.0], scene_px=columns, backend=backend)
    return (time.perf_counter() - start) * 1e3, out


def phase_rows(udc, backend: str, columns: int):
    # The second call of each a column narrower: a fresh operator (the job keeps the last ones).
    cpu_first, cpu = phase_restore(udc, "cpu", columns)
    cpu_warm, _ = phase_restore(udc, "cpu", columns - 1)
    gpu_first, gpu = phase_restore(udc, backend, columns)
    gpu_warm, _ = phase_restore(udc, backend, columns - 1)
    return {
        "cpu_first_ms": cpu_first,
        "cpu_warm_ms": cpu_warm,
        "gpu_first_ms": gpu_first,
        "gpu_warm_ms": gpu_warm,
        "ltr_rel_diff": abs(gpu["ltr"] / cpu["ltr"] - 1),
        "psnr_diff_db": abs(gpu["runs"][0]["psnr_db"] - cpu["runs"][0]["psnr_db"]),
    }


def v_row(udc, backend: str, preview: bool):
    def run(b: str):
        start = time.perf_counter()
        out = udc.phase.invertibility(relay="wrapped-display", preview=preview, backend=b)
        return (time.perf_counter() - start) * 1e3, out

    cpu_ms, cpu = run("cpu")
    gpu_ms, gpu = run(backend)
    diff = max(abs(g / c - 1) for rc, rg in zip(cpu["v"], gpu["v"]) for c, g in zip(rc, rg))
    return {
        "cpu_ms": cpu_ms,
        "gpu_ms": gpu_ms,
        "v_max_rel_diff": diff,
        "device_transforms": gpu.get("backend", {}).get("device_transforms", 0),
    }


if __name__ == "__main__":
    main()
