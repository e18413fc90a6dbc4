#!/usr/bin/env bash
# Regenerates the studio's icon PNGs (assets/icon/hicolor/<N>x<N>/apps/udc-studio.png, the
# freedesktop hicolor layout) from the hand-written assets/icon/udc-studio.svg, and copies the
# SVG to hicolor/scalable/apps. The 256 px PNG is also embedded in the binary as the window icon,
# so re-run this after editing the SVG and commit the PNGs with it.
#
# Needs `rsvg-convert` (Debian's librsvg2-bin); when it is missing and this runs as root, it is
# installed with apt-get.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
svg="$here/udc-studio.svg"
sizes=(16 22 24 32 48 64 128 256 512)

if ! command -v rsvg-convert >/dev/null 2>&1; then
    if [[ "$(id -u)" -eq 0 ]]; then
        apt-get update
        apt-get install -y librsvg2-bin
    else
        echo "render.sh: rsvg-convert not found; install librsvg2-bin (apt-get install librsvg2-bin)" >&2
        exit 1
    fi
fi

for n in "${sizes[@]}"; do
    out="$here/hicolor/${n}x${n}/apps"
    mkdir -p "$out"
    rsvg-convert --width "$n" --height "$n" --format png --output "$out/udc-studio.png" "$svg"
done

mkdir -p "$here/hicolor/scalable/apps"
cp "$svg" "$here/hicolor/scalable/apps/udc-studio.svg"
