#!/usr/bin/env python3
"""udc_studio from Python beside the same analysis in Rust, and beside HCIPy and prysm.

The job is benches/numpy_reference.py's: the T-OLED 150-DPI design (`toled-150dpi`) with the
thesis's iccp21 recipe (f = 10 mm, 4-mm pupil, δ1 = 8 µm, 610/530/470 nm on FFT grids of
1524/1324/1174, a 294-px window of 2-µm pixels integrating 4 × 4 fine samples), then the MTF and
the area under its radial minimum. One run measures, on the same machine:

  (a) `udc_studio.analyze("toled-150dpi")` at full quality, wall time around the call;
  (b) the same call inside Rust: its `call_ms`, timed in the native module around the work the
      call does (the analysis and the advice on its warnings, as `udc-studio analyze` does);
      (a) / (b) is the cost of the Python boundary, held to ≤ 1.10;
  the CLI, `udc-studio analyze --preset toled-150dpi --json` as whole processes (with --cli);
  (c) HCIPy and prysm doing the same job as closely as each allows (the notes say what differs).

Every tool runs once to warm up (plans, caches, thread pools), then the timed runs go in rounds
(each tool once per round) so that load from other work on the machine falls on all of them.

Usage: python_peers.py [--runs N] [--cli PATH] [--skip-peers]
  --runs N      timed runs of each tool after one warm-up (default 5); medians are reported
  --cli PATH    also time the `udc-studio` binary at PATH as whole processes
  --skip-peers  only udc_studio (and the CLI): no HCIPy or prysm

Without an installed `udc_studio` the package is staged from this checkout as
python/tests/conftest.py does (target/debug/lib_native.so from `cargo build`, or
$UDC_NATIVE_LIB). HCIPy and prysm: `python3 -m pip install hcipy prysm`.
The last line printed is one JSON object.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

BENCHES = Path(__file__).resolve().parent
REPO = BENCHES.parent
sys.path.insert(0, str(BENCHES))

# The recipe is numpy_reference.py's, so the two scripts cannot drift apart.
from numpy_reference import (  # noqa: E402
    CHANNELS,
    DELTA1_UM,
    FOCAL_MM,
    M_MAX,
    PUPIL_D_UM,
    SAMPLES_PER_PX,
    SLIT_COLS,
    TILE_CELLS,
    WINDOW_PX,
    ring_index,
    trapezoid,
)

PRESET = "toled-150dpi"
FOCAL_UM = FOCAL_MM * 1e3
# The T-OLED tile in µm: its cells are one pupil sample each (8 µm), 21 of them per 168-µm
# pixel, the slit 5 cells (40 µm) wide. The optical axis sits on the centre of cell 6 of a tile
# (numpy_reference.py: sample M_MAX/2 lands on cell 6), so every slit is centred
# (10 - 6) · 8 = 32 µm right of a multiple of the pitch.
CELL_UM = DELTA1_UM
PITCH_UM = TILE_CELLS * CELL_UM
SLIT_WIDTH_UM = len(SLIT_COLS) * CELL_UM
AXIS_CELL = (M_MAX // 2) % TILE_CELLS
SLIT_OFFSET_UM = (statistics.mean(SLIT_COLS) - AXIS_CELL) * CELL_UM
# Pupil samples at k · δ1, k = -250 … 250: the disc and nothing else. The peers' transforms
# evaluate the field at any focal sampling, so they need no zero padding here.
PUPIL_HALF_SAMPLES = round(PUPIL_D_UM / 2 / DELTA1_UM)
PUPIL_SAMPLES = 2 * PUPIL_HALF_SAMPLES + 1
# The window in fine samples: offsets -588 … 587 from the axis, as numpy_reference.py.
FINE_SPAN = WINDOW_PX * SAMPLES_PER_PX
GOAL_PYTHON_OVER_RUST = 1.10


def fine_sample_um(wavelength_nm: float, fft_size: int) -> float:
    """The focal-plane spacing of a `fft_size` grid of δ1 samples: λ f / (M δ1), ≈ 0.5 µm."""
    return wavelength_nm * 1e-3 * FOCAL_UM / (fft_size * DELTA1_UM)


def slit_centres_um() -> np.ndarray:
    """x of every slit that reaches into the pupil, µm from the axis."""
    reach_um = PUPIL_D_UM / 2 + SLIT_WIDTH_UM / 2
    first = int(np.ceil((-reach_um - SLIT_OFFSET_UM) / PITCH_UM))
    last = int(np.floor((reach_um - SLIT_OFFSET_UM) / PITCH_UM))
    return SLIT_OFFSET_UM + PITCH_UM * np.arange(first, last + 1)


def sensor_psf(fine: np.ndarray) -> np.ndarray:
    """The 294-px PSF (sums to 1) from |field|² on the window's 1176² fine samples."""
    psf = fine.reshape(WINDOW_PX, SAMPLES_PER_PX, WINDOW_PX, SAMPLES_PER_PX).sum(axis=(1, 3))
    return psf / psf.sum()


RINGS = ring_index(WINDOW_PX)


def auc_radial_min(mtf_centred: np.ndarray) -> float:
    """Area under the radially-minimum MTF, exactly as numpy_reference.mtf_figures bins it."""
    half = WINDOW_PX // 2
    keep = RINGS < half
    rmin = np.full(half, np.inf)
    np.minimum.at(rmin, RINGS[keep], mtf_centred[keep])
    return trapezoid(rmin, 1.0 / WINDOW_PX)


def median(values):
    return statistics.median(values) if values else None


# --- udc_studio -----------------------------------------------------------------------------


def import_udc_studio():
    """The installed package, or this checkout's staged as python/tests/conftest.py does."""
    try:
        import udc_studio

        return udc_studio, "installed"
    except ImportError:
        pass
    sys.path.insert(0, str(REPO / "python"))
    from stage import stage  # the tests' staging (python/stage.py)

    sys.path.pop(0)
    try:
        native = stage()
    except RuntimeError as e:
        sys.exit(str(e))
    import udc_studio

    return udc_studio, f"staged from {native}"


def cli_job(cli: Path):
    def run():
        done = subprocess.run(
            [str(cli), "analyze", "--preset", PRESET, "--json"],
            capture_output=True,
            text=True,
            check=True,
        )
        return json.loads(done.stdout)

    return run


# --- the peers --------------------------------------------------------------------------------


class HcipyJob:
    """The job in HCIPy: apertures as Field generators, a FraunhoferPropagator per channel.

    Units are µm throughout (HCIPy takes any consistent unit): pupil coordinates are then exact
    multiples of 8, so samples on the pupil's rim are inside, as in ours. The grids and
    propagators depend only on the optics and are built once, like our FFT plans; each call
    draws the aperture and propagates.
    """

    name = "HCIPy"
    key = "hcipy"

    def __init__(self):
        import hcipy

        self.hcipy = hcipy
        self.version = hcipy.__version__
        # Two-element dims: a scalar would make a 1-D grid.
        self.pupil_grid = hcipy.make_uniform_grid(
            [PUPIL_SAMPLES] * 2, [PUPIL_SAMPLES * DELTA1_UM] * 2, has_center=True
        )
        self.channels = []
        self.transforms = []
        for name, wavelength_nm, fft_size in CHANNELS:
            step_um = fine_sample_um(wavelength_nm, fft_size)
            # Even size with has_center: offsets -588 … 587 fine samples, the axis on one.
            focal_grid = hcipy.make_uniform_grid(
                [FINE_SPAN] * 2, [FINE_SPAN * step_um] * 2, has_center=True
            )
            propagator = hcipy.FraunhoferPropagator(self.pupil_grid, focal_grid, FOCAL_UM)
            self.channels.append((name, wavelength_nm * 1e-3, propagator))
            # The transform FraunhoferPropagator will pick for this channel (the same call).
            uv_grid = focal_grid.scaled(2 * np.pi / (FOCAL_UM * wavelength_nm * 1e-3))
            chosen = hcipy.make_fourier_transform(self.pupil_grid, uv_grid)
            padded = getattr(chosen, "internal_shape", None)
            size = "" if padded is None else f" of {padded[0]}²"
            self.transforms.append(f"{name} {type(chosen).__name__}{size}")

    def __call__(self):
        hcipy = self.hcipy
        grid = self.pupil_grid
        pupil = hcipy.make_circular_aperture(PUPIL_D_UM)(grid)
        slits = grid.zeros()
        for x_um in slit_centres_um():
            # Full height: any height beyond the pupil's.
            slits += hcipy.make_rectangular_aperture(
                (SLIT_WIDTH_UM, 2 * PUPIL_D_UM), center=(x_um, 0.0)
            )(grid)
        aperture = pupil * slits
        aucs = {}
        for name, wavelength_um, propagator in self.channels:
            focal = propagator.forward(hcipy.Wavefront(aperture, wavelength_um))
            psf = sensor_psf(np.asarray(focal.power).reshape(FINE_SPAN, FINE_SPAN))
            # HCIPy has no MTF of a PSF: numpy's FFT, as numpy_reference.py.
            mtf = np.fft.fftshift(np.abs(np.fft.fft2(psf)))
            aucs[name] = auc_radial_min(mtf)
        return aucs

    def notes(self):
        return [
            "aperture: make_circular_aperture(4 mm) × the sum of "
            f"{len(slit_centres_um())} make_rectangular_aperture slits, "
            f"{PUPIL_SAMPLES}² samples of 8 µm (ours: the M² zero-padded grid)",
            "propagation: FraunhoferPropagator straight onto the window's fine grid at ours' "
            f"λf/(Mδ1) spacing; HCIPy chose {', '.join(self.transforms)} "
            "(ours: an FFT of the M² grid, M = 1524, 1324, 1174, then the window cut out)",
            "B: the window's outermost fine row and column (offsets -588 and +587) lie beyond "
            "ours' 1174-point grid, which counts them as zero; HCIPy computes them",
            "MTF: numpy FFT of the PSF (HCIPy has no OTF routine)",
        ]


class PrysmJob:
    """The job in prysm: geometry masks, Wavefront.focus_fixed_sampling (matrix DFT), otf.

    Geometry is drawn in µm, exact multiples of 8 as in ours; prysm's Wavefront takes the pupil
    spacing in mm, the wavelength in µm, the focal length in mm and the focal spacing in µm.
    prysm keeps its DFT matrices in a module cache, so the warm calls reuse them.
    """

    name = "prysm"
    key = "prysm"

    def __init__(self):
        import prysm
        from prysm import coordinates, geometry, otf, propagation

        self.version = prysm.__version__
        self.coordinates, self.geometry = coordinates, geometry
        self.otf, self.propagation = otf, propagation

    def __call__(self):
        coordinates, geometry = self.coordinates, self.geometry
        x_um, y_um = coordinates.make_xy_grid(PUPIL_SAMPLES, dx=DELTA1_UM)
        r_um, _ = coordinates.cart_to_polar(x_um, y_um)
        pupil = geometry.circle(PUPIL_D_UM / 2, r_um)
        # rectangle() takes half-widths (its code tests |x| <= width), whatever its doc says.
        slits = np.logical_or.reduce(
            [
                geometry.rectangle(SLIT_WIDTH_UM / 2, x_um - c_um, y_um, height=PUPIL_D_UM)
                for c_um in slit_centres_um()
            ]
        )
        aperture = (pupil & slits).astype(np.float64)
        aucs = {}
        for name, wavelength_nm, fft_size in CHANNELS:
            step_um = fine_sample_um(wavelength_nm, fft_size)
            wavefront = self.propagation.Wavefront.from_amp_and_phase(
                aperture, None, wavelength_nm * 1e-3, DELTA1_UM * 1e-3
            )
            focal = wavefront.focus_fixed_sampling(FOCAL_MM, step_um, FINE_SPAN, method="mdft")
            psf = sensor_psf(focal.intensity.data)
            mtf = self.otf.mtf_from_psf(psf, step_um * SAMPLES_PER_PX).data
            aucs[name] = auc_radial_min(mtf)
        return aucs

    def notes(self):
        return [
            f"aperture: geometry.circle(2 mm) & {len(slit_centres_um())} geometry.rectangle "
            f"slits, {PUPIL_SAMPLES}² samples of 8 µm",
            "propagation: Wavefront.focus_fixed_sampling(method='mdft'), a matrix DFT straight "
            "onto the window's fine grid at ours' λf/(Mδ1) spacing; B's outermost fine row and "
            "column are computed, where ours counts them as zero (as for HCIPy)",
            "MTF: otf.mtf_from_psf; the radial minimum is ours' ring binning (prysm's "
            "Slices.azmin interpolates onto a polar grid instead)",
        ]


# --- the run ----------------------------------------------------------------------------------


def timed(job):
    t0 = time.perf_counter()
    result = job()
    return (time.perf_counter() - t0) * 1e3, result


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5, help="timed runs after one warm-up")
    ap.add_argument("--cli", type=Path, help="also time this udc-studio binary as processes")
    ap.add_argument("--skip-peers", action="store_true", help="no HCIPy or prysm")
    args = ap.parse_args()
    runs = max(args.runs, 1)
    load_at_start = " ".join(Path("/proc/loadavg").read_text().split()[:3])

    udc, origin = import_udc_studio()
    design = udc.Design.from_preset(PRESET)

    jobs = {"udc_studio": lambda: udc.analyze(PRESET)}
    if args.cli:
        jobs["cli"] = cli_job(args.cli)
    peers = []
    if not args.skip_peers:
        peers = [HcipyJob(), PrysmJob()]
        for peer in peers:
            jobs[peer.key] = peer

    first_ms, first = {}, {}
    for key, job in jobs.items():
        first_ms[key], first[key] = timed(job)
    # `analyze` also advises on each warning, and checks every fix it advises with a preview
    # analysis of the fixed design: work inside (a) that (b) does not time. Analysing the
    # advised designs at preview shows what that check costs.
    first_json = json.loads(first["udc_studio"].to_json())
    advice = [a for a in first_json.get("advice", []) if a.get("fix")]
    advised = [
        design.with_(optics={k.split(".", 1)[1]: v for k, v in a["fix"]["set"].items()})
        for a in advice
    ]
    for d in advised:
        udc.analyze(d, "preview")
    # A native call with next to no work: the least any call costs.
    tiny_image = np.zeros((16, 16))
    udc.denoise(tiny_image, 0.01)

    times_ms = {key: [] for key in jobs}
    results = {key: [] for key in jobs}
    advice_ms, floor_ms = [], []
    for _ in range(runs):
        for key, job in jobs.items():
            ms, result = timed(job)
            times_ms[key].append(ms)
            results[key].append(result)
        advice_ms.append(sum(udc.analyze(d, "preview").elapsed_ms for d in advised))
        floor_ms.append(timed(lambda: udc.denoise(tiny_image, 0.01))[0])

    ours = results["udc_studio"][-1]
    rust_ms = [a.call_ms for a in results["udc_studio"]]
    python_ms = median(times_ms["udc_studio"])
    in_rust_ms = median(rust_ms)
    ratio = python_ms / in_rust_ms
    advice_median_ms = median(advice_ms)
    # Paired within each round, so a burst of load elsewhere falls on both sides.
    outside_ms = median([a - b for a, b in zip(times_ms["udc_studio"], rust_ms)])
    names = list(ours.channels)
    aucs = {"udc_studio": {n: float(v) for n, v in zip(names, ours.auc)}}
    for peer in peers:
        aucs[peer.key] = results[peer.key][-1]

    # --- the table
    print(
        f"udc_studio {udc.__version__} ({origin}); numpy {np.__version__}"
        + "".join(f"; {p.name} {p.version}" for p in peers)
        + f"; Python {platform.python_version()}; {os.cpu_count()} cores; "
        f"load average at start {load_at_start}"
    )
    print(
        f"{PRESET} at full quality: {len(names)} channels; median of {runs} runs after one "
        "warm-up, the tools taking turns"
    )
    print()
    head = f"{'':46} {'first ms':>9} {'median ms':>10}  " + "  ".join(
        f"{'AUC ' + n:>10}" for n in names
    )
    print(head)
    print("-" * len(head))

    def line(label, first, med, auc=None):
        shown = "" if auc is None else "  ".join(f"{auc[n]:10.7f}" for n in names)
        first_text = "" if first is None else f"{first:9.1f}"
        print(f"{label:46} {first_text:>9} {med:10.1f}  {shown}")

    line("(a) udc_studio.analyze from Python", first_ms["udc_studio"], python_ms,
         aucs["udc_studio"])
    line("(b) the same call inside Rust (its call_ms)", None, in_rust_ms)
    if args.cli:
        cli_aucs = {c["name"]: c["auc_radial_min"] for c in results["cli"][-1]["channels"]}
        line("CLI analyze --json, whole process", first_ms["cli"], median(times_ms["cli"]),
             cli_aucs)
    for peer in peers:
        line(
            f"(c) {peer.name} {peer.version}",
            first_ms[peer.key],
            median(times_ms[peer.key]),
            aucs[peer.key],
        )
    print()

    verdict = "pass" if ratio <= GOAL_PYTHON_OVER_RUST else "FAIL"
    print(
        f"Python / Rust, (a) / (b): {ratio:.2f}×  (goal ≤ {GOAL_PYTHON_OVER_RUST:.2f}×: "
        f"{verdict}); (a) − (b), paired per round: {outside_ms:.1f} ms"
    )
    fixes = "; ".join(a["fix"]["summary"] for a in advice) or "none"
    print(
        f"  (b) includes the advice on the design's warnings (fixes checked: {fixes}; "
        f"alone {advice_median_ms:.1f} ms, their preview analyses' elapsed_ms)"
    )
    print(
        "  the least a native call costs (denoise of 16×16 zeros, from Python): "
        f"{median(floor_ms):.2f} ms"
    )
    for peer in peers:
        t = median(times_ms[peer.key])
        rel = ", ".join(
            f"{n} {aucs[peer.key][n] / aucs['udc_studio'][n] - 1.0:+.1e}" for n in names
        )
        print(
            f"{peer.name} / udc_studio: {t / python_ms:.2f}× (a), {t / in_rust_ms:.2f}× (b); "
            f"AUC relative to ours: {rel}"
        )
    if peers:
        print()
        print("What differs from ours. Both peers sample the same binary aperture at the same")
        print("points, evaluate the same focal samples, sum 4 × 4 of them per pixel and take the")
        print("same AUC; ours also computes the LTR, radial means, L_inv, energy checks and")
        print("advice:")
        for peer in peers:
            for note in peer.notes():
                print(f"  {peer.name}: {note}")

    summary = {
        "design": PRESET,
        "quality": "full",
        "runs": runs,
        "python_ms": python_ms,
        "rust_ms": in_rust_ms,
        "python_over_rust": ratio,
        "advice_check_ms": advice_median_ms,
        "python_minus_rust_ms": outside_ms,
        "call_floor_ms": median(floor_ms),
        "cli_ms": median(times_ms["cli"]) if args.cli else None,
        "auc_radial_min": aucs,
        "runs_ms": {**times_ms, "rust": rust_ms},
        "first_ms": first_ms,
        "load_at_start": load_at_start,
        "python": platform.python_version(),
        "numpy": np.__version__,
    }
    for peer in peers:
        t = median(times_ms[peer.key])
        summary[f"{peer.key}_ms"] = t
        summary[f"{peer.key}_over_udc_python"] = t / python_ms
        summary[f"{peer.key}_over_udc_rust"] = t / in_rust_ms
        summary[peer.key] = peer.version
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
