#!/usr/bin/env bash
# How robust the collision response is where rigid impact zones lock: the five-turn twist at
# 16x8, turned at several speeds around the ctest's 720 deg/s (CollisionScenes.FiveTurnTwist...),
# 75 frames each (2.5 s), checked after every frame by weft_check_scene --keep-going (exact
# triangle intersections, edges over the strain limit). One line per speed: frames run (fewer than
# 75 when the run diverged), frames ending over the strain limit, frames with intersecting
# triangle pairs, frames with a step reported unclean, the largest edge stretch.
#   bench/twist_sweep.sh [speed ...]     (default: 660 680 700 720 740 760 780)
#   FRAMES=150 bench/twist_sweep.sh 320 340 360 380 400   (the shipped speed's five turns)
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cmake --build build/release --target weft_check_scene -j2 >/dev/null || exit 100
speeds=("$@")
[ ${#speeds[@]} -eq 0 ] && speeds=(660 680 700 720 740 760 780)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "deg/s frames over_limit intersecting unclean largest_stretch"
for speed in "${speeds[@]}"; do
  build/release/bench/weft_check_scene scenes/twist_five_turns.json --frames "${FRAMES:-75}" --keep-going \
    --set 'cloths.0.grid.resolution=[16,8]' --set "cloths.0.moving_pins.0.angular_velocity_degrees=$speed" \
    --set solver.newton.max_iterations=10 --set solver.newton.tolerance=1e-3 \
    > "$out/run.csv" 2> "$out/run.err"
  # Columns: 6 intersecting_pairs, 16 collisions_clean, 18 largest_edge_stretch (strain limit 1).
  awk -F, -v speed="$speed" 'NR > 2 {
      frames++; over += ($18 > 2.0 * 1.001001); hit += ($6 > 0); unclean += ($16 == 0)
      if ($18 > worst) worst = $18
    } END { printf "%s %d %d %d %d %.3f\n", speed, frames, over, hit, unclean, worst }' "$out/run.csv"
done
