#!/usr/bin/env bash
# Regenerates the screenshots of the README and the book (docs/src): renders the real studio headless with egui_kittest on
# wgpu (lavapipe, from Debian's mesa-vulkan-drivers) and saves them here.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! dpkg -s mesa-vulkan-drivers >/dev/null 2>&1; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers libvulkan1
fi
UDC_SCREENSHOTS_DIR="$PWD/screenshots" cargo test --test suite -- --test-threads=1 screenshots:: views:: field_depth_view:: appearance_view:: measured_panel:: presentation:: lessons_panel:: study::
ls -l screenshots/*.png
