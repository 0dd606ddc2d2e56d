#!/usr/bin/env bash
# The viewer's own frame times while the simulation steps on its thread: drape_sphere at 32x32,
# 64x64 and 128x128, played for SECONDS (default 12) under xvfb-run with --frame-times, one CSV row
# per size (the first 2 s left out): drawn frames, the UI thread's work per frame (input, panels,
# taking in the step, drawing up to the buffer swap), the frame interval (swap included: under
# xvfb that is Mesa's software rasteriser, sharing the cores with the solver) and the step time (the median over the steps drawn; a frame
# draws the last finished step, which may be several steps after the one before).
#   bench/viewer_frame_times.sh [SECONDS] > bench/results/viewer/DATE_frame_times.csv
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
weft=${WEFT:-$root/build/release/src/weft}
seconds=${1:-12}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# $(date -u +%F) $(git -C "$root" rev-parse --short HEAD), $(nproc) cores; bench/viewer_frame_times.sh $seconds"
echo "resolution,threads,frames_drawn,work_ms_median,work_ms_p95,interval_ms_median,interval_ms_p95,step_ms_median,steps_per_second"
for n in 32 64 128; do
  xvfb-run -a -s "-screen 0 1280x720x24" "$weft" "$root/scenes/drape_sphere.json" \
    --set "cloths.0.grid.resolution=[$n,$n]" --threads 1 --play --quit-after "$seconds" \
    --frame-times "$tmp/$n.csv" 2>/dev/null
  awk -F, -v n="$n" '
    NR > 1 && $2 > 2 {
      work[++k] = $3; interval[k] = $4
      if ($5 != last) step[++s] = $6  # each step drawn once, however many frames showed it
      if (!first) first = $5; last = $5; t0 = t0 ? t0 : $2; t1 = $2
    }
    function sort(a, m,   i, j, x) { for (i = 2; i <= m; i++) { x = a[i]; for (j = i - 1; j > 0 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } }
    END {
      sort(work, k); sort(interval, k); sort(step, s)
      printf "%d,1,%d,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f\n", n, k, work[int(k / 2) + 1], work[int(0.95 * k)],
             interval[int(k / 2) + 1], interval[int(0.95 * k)], step[int(s / 2) + 1], (last - first) / (t1 - t0)
    }' "$tmp/$n.csv"
done
