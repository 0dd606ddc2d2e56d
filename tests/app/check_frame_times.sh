#!/usr/bin/env bash
# Checks a viewer's --frame-times CSV for drawing that does not wait for steps: the window kept
# drawing one step for at least MIN_RUN frames in a row (it drew while the next was computed), and
# the steps it drew advanced (it took finished ones in).
# Usage: check_frame_times.sh FILE MIN_RUN
set -euo pipefail
file=$1
min_run=$2
[[ -s $file ]] || { echo "FAIL: $file is missing or empty"; exit 1; }
header=$(head -n 1 "$file")
[[ $header == frame,start_s,work_ms,interval_ms,shown_step,step_ms,simulated_s ]] ||
  { echo "FAIL: $file: unexpected header: $header"; exit 1; }
awk -F, -v min_run="$min_run" -v file="$file" '
  NR == 1 { next }
  {
    frames++
    if (NR > 2 && $5 == previous) run++; else run = 1
    if (run > longest) longest = run
    if (NR == 2) first = $5
    previous = $5
  }
  END {
    printf "%s: %d frames drawn, steps %d to %d, at most %d frames on one step\n", file, frames, first, previous, longest
    if (previous <= first) { print "FAIL: no finished step was drawn"; exit 1 }
    if (longest < min_run) { printf "FAIL: never %d frames while one step ran: drawing waits for steps\n", min_run; exit 1 }
  }' "$file"
