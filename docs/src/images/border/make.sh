#!/usr/bin/env bash
# Regenerates the border-policy pictures of docs/src/display/mask-export.md: the disc lattice's
# 3 × 3-pixel block under each policy, written by the studio's own PNG export (white = drawn).
# Usage: docs/src/images/border/make.sh [path/to/udc-studio]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../../../../target/debug/udc-studio}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
shot() {
    local name="$1"
    shift
    "$bin" export --preset disc-lattice --format png --region 3x3 --um-per-px 2 --png-bits 8 \
        --deterministic --out "$tmp/$name.png" "$@" > /dev/null
    cp "$tmp/$name.png" "$here/$name.png"
}
shot open-cut --tone open --border cut
shot open-drop --tone open --border drop
shot open-extend --tone open --border extend
shot open-margin --tone open --border margin
shot chrome-cut --tone chrome --border cut
shot chrome-margin --tone chrome --border margin
