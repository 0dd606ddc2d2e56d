#!/usr/bin/env bash
# Runs every collision scene to its end with the invariant check after every frame (zero
# intersecting triangle pairs by the standard definition, zero cloth vertices inside a collider,
# every edge within collision.strain_limit where one is set), writing
# out/collision_scenes/<scene>.csv. Exit code: the number of scenes that failed.
#   bench/collision_scenes.sh [scene ...]     (default: all eight; THREADS=n for OpenMP threads)
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cmake --build build/release --target weft_check_scene -j2 >/dev/null || exit 100
scenes=("$@")
[ ${#scenes[@]} -eq 0 ] && scenes=(drape_sphere two_sheets tumble_dryer twist twist_five_turns fast_drop friction_slope soft_balls)
mkdir -p out/collision_scenes
failed=0
for scene in "${scenes[@]}"; do
  start=$(date +%s)
  if build/release/bench/weft_check_scene "scenes/$scene.json" --threads "${THREADS:-1}" \
      > "out/collision_scenes/$scene.csv" 2> "out/collision_scenes/$scene.err"; then
    status=clean
  else
    status="FAILED: $(cat "out/collision_scenes/$scene.err")"
    failed=$((failed + 1))
  fi
  frames=$(($(wc -l < "out/collision_scenes/$scene.csv") - 2))
  echo "$scene: $frames frames, $(( $(date +%s) - start )) s, $status"
done
exit $failed
