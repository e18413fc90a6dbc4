#!/usr/bin/env bash
# Sweep throughput against a shell loop over the CLI, and the sweep's peak memory for 100 and
# 1000 points (it must not grow with the points). Prints a Markdown table for benches/REPORT.md.
# Usage: bash benches/sweep.sh   (builds the release binary first)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-$root/target}/release/udc-studio"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }

spec() { # preset, last seed
    printf 'job = "analyze"\n[base]\npreset = "%s"\n[[axis]]\nparam = "seed"\nrange = { start = 0, stop = %s }\n' "$1" "$2"
}

echo "| measurement | value | goal | pass/fail |"
echo "| --- | --- | --- | --- |"
for preset in toled-150dpi l2inv-random; do
    spec "$preset" 99 >"$work/$preset.toml"
    t0=$(now); "$bin" sweep "$work/$preset.toml" --out "$work/out-$preset" --threads 2 --quiet --no-plots; t1=$(now)
    sweep_rate=$(echo "100 / ($t1 - $t0)" | bc -l)
    t0=$(now)
    for s in $(seq 0 19); do "$bin" analyze --preset "$preset" --seed "$s" --json >/dev/null; done
    t1=$(now)
    loop_rate=$(echo "20 / ($t1 - $t0)" | bc -l)
    ratio=$(echo "$sweep_rate / $loop_rate" | bc -l)
    pass=$(echo "$sweep_rate >= 50" | bc -l)
    printf '| `sweep` of 100 %s points, 2 threads | %.1f points/s | ≥ 50 points/s | %s |\n' "$preset" "$sweep_rate" "$([ "$pass" = 1 ] && echo pass || echo fail)"
    pass=$(echo "$ratio >= 4" | bc -l)
    printf '| shell loop over `analyze` (%s, 20 points) | %.1f points/s; sweep %.1f× faster | ≥ 4× | %s |\n' "$preset" "$loop_rate" "$ratio" "$([ "$pass" = 1 ] && echo pass || echo fail)"
done
for n in 100 1000; do
    spec toled-150dpi $((n - 1)) >"$work/mem$n.toml"
    kb=$(/usr/bin/time -f %M "$bin" sweep "$work/mem$n.toml" --out "$work/mem$n" --threads 2 --quiet --no-plots 2>&1 >/dev/null | tail -n 1)
    mb=$(echo "$kb * 1024 / 1000000" | bc -l)
    pass=$(echo "$mb <= 200" | bc -l)
    printf '| peak memory (VmHWM) of a %d-point sweep, 2 threads | %.0f MB | ≤ 200 MB | %s |\n' "$n" "$mb" "$([ "$pass" = 1 ] && echo pass || echo fail)"
done
