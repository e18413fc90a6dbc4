#!/usr/bin/env bash
# Runs the benches and the numpy reference, then writes benches/REPORT.md: median times, peak
# memory and the goals they are held to. Usage: bash benches/report.sh
#
# Numbers come from files, not from scraping console text:
#   <target>/criterion/**/new/{benchmark,estimates}.json  criterion's median (ns) per bench id
#   <target>/udc-bench/analyze-figures.json               AUCs printed by benches/analyze.rs
#   <target>/udc-bench/memory.json                        VmHWM from benches/memory.rs
#   the last line of benches/numpy_reference.py           its AUCs and median time (JSON)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
target="${CARGO_TARGET_DIR:-$root/target}"
python="${PYTHON:-python3}"
logs="$target/udc-bench"
mkdir -p "$logs"

# Other work on the machine skews every median; the report shows the load it started under.
load_before="$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"

# (i) numpy, the only thing the reference needs.
if ! "$python" -c 'import numpy' 2>/dev/null; then
    "$python" -m pip install --quiet numpy
fi

# (ii) the Rust benches. Stale criterion results of a renamed bench are ignored below: only the
# ids this script knows are read.
# ONLY="phase sensor" reruns just those benches (and their numpy references) and reuses the
# other results already under <target>; without it everything runs.
only="${ONLY:-analyze memory studio restore optimize sensor phase}"
runs() { [[ " $only " == *" $1 "* ]]; }
for b in analyze studio restore optimize sensor phase; do
    if runs "$b"; then
        cargo bench --bench "$b" -- --noplot 2>&1 | tee "$logs/$b.log"
    fi
done
if runs memory; then
    cargo bench --bench memory 2>&1 | tee "$logs/memory.log"
fi

# (iii) the numpy references: case (a) and the open aperture for the thesis check; the
# phase-mask V matrix, the same 900 propagations as benches/phase.rs.
if runs analyze; then
    "$python" benches/numpy_reference.py | tee "$logs/numpy.log"
    tail -n 1 "$logs/numpy.log" >"$logs/numpy.json"
    "$python" benches/numpy_reference.py --open --runs 1 | tee "$logs/numpy-open.log"
    tail -n 1 "$logs/numpy-open.log" >"$logs/numpy-open.json"
fi
if runs phase; then
    "$python" benches/phase_numpy.py | tee "$logs/phase-numpy.log"
    tail -n 1 "$logs/phase-numpy.log" >"$logs/phase-numpy.json"
fi

# (iv) the report.
LOAD="$load_before" \
NPROC="$(nproc 2>/dev/null || echo unknown)" \
RUSTC="$(rustc --version 2>/dev/null || echo unknown)" \
CPU="$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)" \
    "$python" - "$target" "$root/benches/REPORT.md" <<'EOF'
import datetime
import glob
import json
import os
import sys

target, out_path = sys.argv[1], sys.argv[2]
bench = os.path.join(target, "udc-bench")


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


# criterion: full_id -> median in ms.
median_ms = {}
for est in glob.glob(os.path.join(target, "criterion", "**", "new", "estimates.json"), recursive=True):
    meta = load(os.path.join(os.path.dirname(est), "benchmark.json"))
    data = load(est)
    if meta and data:
        median_ms[meta["full_id"]] = data["median"]["point_estimate"] / 1e6

figures = load(os.path.join(bench, "analyze-figures.json")) or {}
memory = load(os.path.join(bench, "memory.json")) or {}
numpy_ref = load(os.path.join(bench, "numpy.json")) or {}
numpy_open = load(os.path.join(bench, "numpy-open.json")) or {}

rows = []


def verdict(ok):
    return "—" if ok is None else ("pass" if ok else "**FAIL**")


def row(name, value, unit, goal_text, ok):
    shown = "n/a" if value is None else f"{value:.1f}{unit}"
    rows.append(f"| {name} | {shown} | {goal_text} | {verdict(ok)} |")


def time_row(bench_id, limit_ms=None):
    t = median_ms.get(bench_id)
    ok = None if limit_ms is None else (t is not None and t <= limit_ms)
    row(f"`{bench_id}`", t, "", "—" if limit_ms is None else f"≤ {limit_ms} ms", ok)


time_row("analyze/iccp21/toled-repeat", 150)
time_row("analyze/iccp21/toled-random-d4")
time_row("analyze/preview/toled-repeat-f10", 20)
time_row("analyze/iccp21/toled-repeat-f10")
time_row("analyze/iccp21/open-aperture")
np_ms = numpy_ref.get("median_ms")
row("numpy reference of (a), median of 5", np_ms, "", "—", None)
rust_a = median_ms.get("analyze/iccp21/toled-repeat")
ratio = np_ms / rust_a if np_ms and rust_a else None
rows.append(
    f"| speed ratio numpy / Rust for (a) | {'n/a' if ratio is None else f'{ratio:.1f}×'} | ≥ 4× | "
    f"{verdict(None if ratio is None else ratio >= 4)} |"
)
# The studio (issue 3): a frame while dragging, and committed edit -> first / full result
# through the real worker thread. The first result is full quality at f/2.5 (the preview would
# not agree there) and a preview at f/10.
time_row("studio/frame-while-dragging", 16)
time_row("studio/edit-to/first", 250)
time_row("studio/edit-to/full", 250)
time_row("studio/edit-to/first/f10", 50)
time_row("studio/edit-to/full/f10", 250)
# Capture and restore (issue 7): a 1024×768 colour photo through the T-OLED, Wiener, PSNR/SSIM.
time_row("restore/wiener/toled-1024x768", 300)
time_row("restore/wiener-linear/toled-1024x768")
time_row("restore/cg/toled-256x256")
# The sensor previewer (issue 6): Table 5.4's four strategies on a 1240×846 HDR scene, maps and
# metrics included; and the studio panel's preview (the scene downscaled to 640 px).
time_row("sensor/table54/stilllife-1240x846", 400)
time_row("sensor/preview", 100)
# The optimizer (issue 7): one epoch, and one whole 150-epoch L_inv run timed once.
time_row("optimize/iccp21/epoch")
opt = load(os.path.join(bench, "optimize.json")) or {}
secs = opt.get("seconds")
aucs = ""
if opt.get("auc_before") and opt.get("auc_after"):
    aucs = " (AUC R " + f"{opt['auc_before'][0]:.4f} → {opt['auc_after'][0]:.4f})"
rows.append(
    f"| 150 epochs of `L_inv` optimization, iccp21, one run{aucs} | "
    f"{'n/a' if secs is None else f'{secs:.1f} s'} | ≤ 60 s | {verdict(None if secs is None else secs <= 60)} |"
)
# Phase masks (issue 5): one PSF, the studio's three-channel update, and the whole V matrix
# against numpy doing the same propagations in one run of this script.
time_row("phase/psf-530nm/thesis", 100)
time_row("phase/rgb-vs-toled/thesis")
time_row("phase/rgb-vs-toled/preview")
time_row("phase/rgb-vs-toled/thesis-lenslet-period")
time_row("phase/rgb-vs-toled/optimized-plan")
time_row("phase/rgb-vs-toled/optimized-plan-wrapped")
phase = load(os.path.join(bench, "phase.json")) or {}
phase_np = load(os.path.join(bench, "phase-numpy.json")) or {}
v_s, np_s = phase.get("seconds"), phase_np.get("seconds")
rows.append(
    f"| V matrix, 900 propagations, 600 DPI, T = 1, one run on {phase.get('threads', '?')} threads | "
    f"{'n/a' if v_s is None else f'{v_s:.1f} s'} | ≤ 3 s | {verdict(None if v_s is None else v_s <= 3)} |"
)
row("V matrix in numpy (benches/phase_numpy.py), one run", np_s, " s", "—", None)
vp_s = phase.get("lenslet_period_seconds")
row("V matrix through the lenslet period (entries within "
    f"{phase.get('lenslet_period_worst', float('nan')):.0e} of the whole display), one run",
    vp_s, " s", "≤ 1 s", None if vp_s is None else vp_s <= 1)
operator = load(os.path.join(bench, "phase-operator.json")) or {}
for width, goal in ((256, 3), (512, 10)):
    o_s = operator.get(f"period_{width}_seconds")
    row(f"spectral operator of a {width}-px photo, 30 wavelengths, lenslet period, one run",
        o_s, " s", f"≤ {goal} s", None if o_s is None else o_s <= goal)
row("the same 256-px operator through the whole display", operator.get("whole_256_seconds"),
    " s", "—", None)
row("the optimized λ0 plan's 256-px operator (T = 5, no lenslet period), wrapped display, one run",
    operator.get("plan_wrapped_256_seconds"), " s", "—", None)
row("the same through the whole display", operator.get("plan_whole_256_seconds"), " s", "—", None)
row("the bare T-OLED's 256-px operator through the whole display (the opening's transforms alone)",
    operator.get("toled_whole_256_seconds"), " s", "—", None)
imaging = load(os.path.join(bench, "phase-imaging.json")) or {}
b_s, r_s = imaging.get("blur_seconds"), imaging.get("restore_seconds")
row("phase blur matrix, 1024 directions × R, G, B, thesis sampling, one run", b_s, " s", "≤ 20 s",
    None if b_s is None else b_s <= 20)
row("phase capture + restore, 512×512, one light level, one run", r_s, " s", "≤ 2 s",
    None if r_s is None else r_s <= 2)
v_ratio = np_s / v_s if np_s and v_s else None
rows.append(
    f"| speed ratio numpy / Rust for V | {'n/a' if v_ratio is None else f'{v_ratio:.1f}×'} | ≥ 3× | "
    f"{verdict(None if v_ratio is None else v_ratio >= 3)} |"
)
for case, entry in memory.items():  # the bench writes them in its own order
    peak = entry.get("peak_mb")
    base = entry.get("baseline_mb")
    note = "" if base is None else f" (baseline {base:.1f} MB)"
    rows.append(
        f"| peak memory `{case}`, VmHWM{note} | {'unavailable' if peak is None else f'{peak:.1f} MB'} "
        f"| ≤ 300 MB | {verdict(None if peak is None else peak <= 300)} |"
    )
if not memory:
    rows.append("| peak memory | unavailable | ≤ 300 MB | — |")


# AUC agreement: Rust analyze vs numpy, and the open aperture vs the thesis.
def max_rel(a, b):
    keys = sorted(set(a) & set(b))
    if not keys:
        return None
    return max(abs(a[k] / b[k] - 1.0) for k in keys)


checks = []
for label, bench_id, ref in (
    ("T-OLED (a)", "analyze/iccp21/toled-repeat", numpy_ref),
    ("open aperture (d)", "analyze/iccp21/open-aperture", numpy_open),
):
    rust = figures.get(bench_id, {}).get("auc_radial_min", {})
    rel = max_rel(rust, ref.get("auc_radial_min", {}))
    shown = "n/a" if rel is None else f"{rel:.1e}"
    ok = None if rel is None else rel <= 1e-6
    aucs = ", ".join(f"{k} {v:.6f}" for k, v in rust.items())
    checks.append(f"| {label}: Rust vs numpy AUC ({aucs}) | {shown} | ≤ 1e-6 | {verdict(ok)} |")
rv, nv = phase.get("v"), phase_np.get("v")
if rv and nv:
    rel = max(abs(a / b - 1.0) for ra, rb in zip(rv, nv) for a, b in zip(ra, rb) if b)
    checks.append(
        f"| phase V matrix: Rust vs numpy (900 entries) | {rel:.1e} | ≤ 1e-6 | {verdict(rel <= 1e-6)} |"
    )
else:
    checks.append("| phase V matrix: Rust vs numpy | n/a | ≤ 1e-6 | — |")
thesis = {"R": 0.3068, "G": 0.3170, "B": 0.3274}
rust_open = figures.get("analyze/iccp21/open-aperture", {}).get("auc_radial_min", {})
rel = max_rel(rust_open, thesis)
checks.append(
    f"| open aperture: Rust AUC vs thesis (R 0.3068, G 0.3170, B 0.3274) | "
    f"{'n/a' if rel is None else f'{100 * rel:.3f} %'} | ≤ 0.3 % | "
    f"{verdict(None if rel is None else rel <= 0.003)} |"
)

now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
lines = [
    "# Benchmark report",
    "",
    f"Generated by `benches/report.sh` on {now}; `nproc` = {os.environ.get('NPROC', '?')}"
    + (f" ({os.environ['CPU']})" if os.environ.get("CPU") else "")
    + f"; {os.environ.get('RUSTC', '')}; numpy {numpy_ref.get('numpy', '?')};"
    + f" load average at start {os.environ.get('LOAD', '?')}.",
    "",
    "Times are criterion medians (10 samples) of one `analyze` call after a warm-up call; memory is",
    "the peak resident set (VmHWM, MB = 10⁶ bytes) of a fresh process running one full analyze.",
    "",
    "| bench | median time (ms, or as marked) | goal | pass/fail |",
    "| --- | --- | --- | --- |",
    *rows,
    "",
    "## Numbers agree",
    "",
    "| check | max relative difference | goal | pass/fail |",
    "| --- | --- | --- | --- |",
    *checks,
    "",
]
with open(out_path, "w") as f:
    f.write("\n".join(lines))
print("\n".join(lines))
EOF
