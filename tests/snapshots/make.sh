#!/usr/bin/env bash
# Regenerates the pixel snapshots the tests compare against (the editor, and every workspace at
# 1024×700, 1366×768 and 1920×1080): renders headless with egui_kittest on wgpu (lavapipe).
set -euo pipefail
cd "$(dirname "$0")/../.."
if ! dpkg -s mesa-vulkan-drivers >/dev/null 2>&1; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers libvulkan1
fi
UPDATE_SNAPSHOTS=1 cargo test --test suite -- layouts:: opening_ops::editor_snapshot_matches
ls -l tests/snapshots/*.png
