#!/usr/bin/env bash
# Points per core-hour of each sweep job (one worker thread, release build), for the paper
# plan in docs/src/benchmarks.md. Prints a Markdown table. Usage: bash benches/sweep_plan.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-$root/target}/release/udc-studio"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# name | spec body (base and one axis)
cases=(
"analyze, T-OLED 150 DPI (periodic, R G B)|job = \"analyze\"
[base]
preset = \"toled-150dpi\"
[[axis]]
param = \"seed\"
range = { start = 0, stop = 39 }"
"analyze, L2+inv 150 DPI (random-4, R G B)|job = \"analyze\"
[base]
preset = \"l2inv-random\"
[[axis]]
param = \"seed\"
range = { start = 0, stop = 39 }"
"analyze, T-OLED 600 DPI (R G B)|job = \"analyze\"
[base]
preset = \"toled-600dpi\"
[[axis]]
param = \"seed\"
range = { start = 0, stop = 7 }"
"restore, T-OLED 150 DPI, 256×256 photo, Wiener|job = \"restore\"
[base]
preset = \"toled-150dpi\"
image = \"$root/assets/photos/astronaut_256.png\"
snr-db = 28
[[axis]]
param = \"noise-seed\"
range = { start = 0, stop = 9 }"
"phase-psf, thesis sampling, R G B|job = \"phase-psf\"
[[axis]]
param = \"fold\"
range = { start = 1, stop = 8 }"
"phase-restore, peaks, one light level|job = \"phase-restore\"
[base]
peaks = true
photons = 1000
[[axis]]
param = \"seed\"
range = { start = 0, stop = 3 }"
"sensor, StillLife 620×423, Table 5.4's four strategies|job = \"sensor\"
[base]
hdr = \"$root/assets/hdr/StillLife_620x423.exr\"
[[axis]]
param = \"seed\"
range = { start = 0, stop = 7 }"
)
echo "| job | points per core-hour | s per point (1 thread) |"
echo "| --- | --- | --- |"
i=0
for c in "${cases[@]}"; do
    name="${c%%|*}"; body="${c#*|}"
    printf '%s\n' "$body" >"$work/s$i.toml"
    "$bin" sweep "$work/s$i.toml" --out "$work/o$i" --threads 1 --quiet --no-plots
    rate=$(python3 -c "import json;print(json.load(open('$work/o$i/sweep.json'))['points_per_s'])")
    printf '| %s | %.0f | %.3f |\n' "$name" "$(echo "$rate * 3600" | bc -l)" "$(echo "1 / $rate" | bc -l)"
    i=$((i + 1))
done
