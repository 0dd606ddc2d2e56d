#!/usr/bin/env bash
# End-to-end check of tools/blender/weft_blender.py: records a short drape_sphere run, builds
# the Blender scene headless, checks that the Mesh Cache modifier reproduces the point cache,
# renders one frame with Cycles and checks the image is not blank.
#   tools/blender/test_blender.sh [WEFT_BINARY]   (default build/release/src/weft)
# Exits 0 when Blender is not installed, after saying so (the check is skipped, not failed).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
weft=${1:-$root/build/release/src/weft}

if ! command -v blender >/dev/null 2>&1; then
  echo "test_blender: SKIPPED: Blender is not installed (apt-get install blender, or scripts/install-deps --blender)"
  exit 0
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/weft_blender_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$weft" --headless "$root/scenes/drape_sphere.json" --out "$work/drape" --quiet --frames 12 \
  --set 'cloths.0.grid.resolution=[24,24]'
blender -b --factory-startup --python "$root/tools/blender/weft_blender.py" -- "$work/drape" \
  --frame 12 --samples 8 --resolution 320 180 --output "$work/frame_0012.png" --save "$work/drape.blend" \
  --check >"$work/blender.log" 2>&1 || {
  cat "$work/blender.log"
  echo "test_blender: FAILED (Blender output above)"
  exit 1
}
grep '^weft_blender:' "$work/blender.log"
if [[ ! -s "$work/frame_0012.png" || ! -s "$work/drape.blend" ]]; then
  echo "test_blender: FAILED: no render or no .blend written"
  exit 1
fi
echo "test_blender: passed"
