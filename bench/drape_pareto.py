#!/usr/bin/python3
"""The drape's speed/accuracy trade: wall time against deviation from a converged reference.

    /usr/bin/python3 bench/drape_pareto.py --out out/pareto [--weft build/release/src/weft]
        [--resolution 64] [--threads 1] [--runs 3] [--peers out/peers/results.csv]

Runs scenes/drape_sphere.json headless at N x N vertices, first as a converged reference
(h = 1/960 s, Newton residual 1e-4 m/s, Cholesky), then at every configuration of CONFIGS
(time step, Newton tolerance, Newton iterations capped), each --runs times. Every run's frames
are compared with the reference's frame at the same time (vertex distances, RMS and largest);
its cost is the wall seconds of stepping (stats.csv's step_ms) per simulated second, counted as
bench/peers/run counts it (summarize.weft_stepping), the median of the runs. Writes
  OUT/pareto.csv       one row per configuration: cost, deviations, Newton iterations
  OUT/deviation.csv    one row per configuration x frame: RMS and largest deviation
  OUT/pareto.png       cost against deviation, and deviation over time (needs matplotlib)
With --peers (bench/peers/run's results.csv at the same N), the peers' median wall seconds per
simulated second are marked as vertical lines: their models differ from Weft's, so only their
cost is comparable, not a deviation. A benchmark, not a test: never run by ctest.
The drape is chaotic once the cloth folds: the deviations bound what any accuracy target can ask.
"""
import argparse
import csv
import json
import math
import statistics
import struct
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "scenes" / "drape_sphere.json"
sys.dont_write_bytecode = True  # no __pycache__ left in the source tree
sys.path.insert(0, str(ROOT / "bench" / "peers"))
from summarize import weft_stepping  # noqa: E402  the cost as bench/peers/run counts it

# (label, overrides). The shipped settings are h = 1/240 s and a Newton tolerance of 1e-2 m/s.
REFERENCE = ("reference: h 1/960, tolerance 1e-4, Cholesky",
             {"solver.time_step": 1 / 960, "solver.newton.tolerance": 1e-4,
              "solver.newton.linear_solver": "cholesky", "solver.newton.max_iterations": 200})
CONFIGS = [
    ("h 1/480, tolerance 1e-2", {"solver.time_step": 1 / 480}),
    ("h 1/240, tolerance 1e-2 (shipped)", {}),
    ("h 1/240, tolerance 1e-3", {"solver.newton.tolerance": 1e-3}),
    ("h 1/120, tolerance 1e-2", {"solver.time_step": 1 / 120}),
    ("h 1/60, tolerance 1e-2", {"solver.time_step": 1 / 60}),
    ("h 1/240, 2 Newton iterations a step", {"solver.newton.max_iterations": 2}),
    ("h 1/120, 2 Newton iterations a step", {"solver.time_step": 1 / 120, "solver.newton.max_iterations": 2}),
    ("h 1/120, 2 Newton iterations, 5% limit",
     {"solver.time_step": 1 / 120, "solver.newton.max_iterations": 2, "collision.strain_limit": 0.05}),
    ("fast tier (drape_sphere_fast): h 1/90, 2 Newton iterations, 5% limit",
     {"solver.time_step": 1 / 90, "solver.newton.max_iterations": 2, "collision.strain_limit": 0.05}),
]


def fail(message):
    print(f"bench/drape_pareto.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_pc2(path):
    """Frames of a point cache: a list of lists of (x, y, z)."""
    data = path.read_bytes()
    if len(data) < 32 or data[:12] != b"POINTCACHE2\0":
        fail(f"{path}: not a POINTCACHE2 file")
    _, points, _, _, samples = struct.unpack_from("<iiffi", data, 12)
    if len(data) != 32 + 12 * points * samples:
        fail(f"{path}: {len(data)} bytes, expected {32 + 12 * points * samples} for {points} points x {samples} samples")
    values = struct.unpack_from(f"<{3 * points * samples}f", data, 32)
    return [[values[3 * (s * points + p):3 * (s * points + p) + 3] for p in range(points)] for s in range(samples)]


def simulate(weft, out_dir, resolution, threads, overrides):
    """Runs the drape once with the overrides; returns (wall seconds of stepping per simulated
    second, summary.json)."""
    args = [str(weft), "--headless", str(SCENE), "--out", str(out_dir), "--quiet", "--threads", str(threads),
            "--fixed-threads", "--set", f"cloths.0.grid.resolution=[{resolution},{resolution}]"]
    for path, value in overrides.items():
        args += ["--set", f"{path}={value!r}" if not isinstance(value, str) else f"{path}={value}"]
    result = subprocess.run(args, capture_output=True, text=True)
    summary_path = out_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    if result.returncode != 0 or summary.get("status") != "complete":
        fail(f"{' '.join(args)} exited {result.returncode}: {result.stderr.strip()[-400:]}")
    stepping = weft_stepping(out_dir)
    return stepping["wall_s"] / stepping["simulated_s"], summary


def deviations(frames, reference):
    """Per frame: (RMS, largest) vertex distance to the reference's frame, in metres."""
    rows = []
    for frame, ref in zip(frames, reference):
        squares = [(a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2 for a, b in zip(frame, ref)]
        rows.append((math.sqrt(sum(squares) / len(squares)), math.sqrt(max(squares))))
    return rows


def peer_costs(results_csv, resolution):
    """{label: median wall seconds per simulated second} of the peers at this resolution."""
    runs = {}
    with Path(results_csv).open() as f:
        for row in csv.DictReader(f):
            if row["simulator"].startswith("weft") or row["status"] != "ok" or int(row["N"]) != resolution:
                continue
            label = f"{row['simulator'].capitalize()}, {row['threads']} thread{'s' if row['threads'] != '1' else ''}"
            runs.setdefault(label, []).append(float(row["wall_per_sim_s"]))
    return {label: statistics.median(values) for label, values in sorted(runs.items())}


def plot(out, rows, per_frame, fps, peers, resolution, threads):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plots: skipped, matplotlib missing (Debian: python3-matplotlib)")
        return
    fig, (cost_ax, time_ax) = plt.subplots(1, 2, figsize=(13, 5.2))
    for i, row in enumerate(rows):
        colour = f"C{i}"
        cost_ax.scatter(row["wall_per_sim_s"], 1000 * row["rms_mean_m"], color=colour, zorder=3)
        cost_ax.annotate(row["label"], (row["wall_per_sim_s"], 1000 * row["rms_mean_m"]), fontsize=7,
                         xytext=(4, 3), textcoords="offset points")
        series = per_frame[row["label"]]
        time_ax.plot([k / fps for k in range(len(series))], [1000 * rms for rms, _ in series], color=colour,
                     label=row["label"])
    for k, (label, cost) in enumerate(peers.items()):
        cost_ax.axvline(cost, color="grey", linestyle=("--", ":", "-.")[k % 3], linewidth=1)
        cost_ax.annotate(f"{label}: {cost:.2f} s", (cost, 0.02 + 0.45 * (k % 2)), xycoords=("data", "axes fraction"),
                         rotation=90, fontsize=7, xytext=(-9, 0), textcoords="offset points", va="bottom")
    cost_ax.axvline(1.0, color="black", linewidth=0.8)
    cost_ax.annotate("real time", (1.0, 0.98), xycoords=("data", "axes fraction"), rotation=90, fontsize=7,
                     xytext=(-9, 0), textcoords="offset points", va="top")
    cost_ax.set_xscale("log")
    cost_ax.set_yscale("log")
    cost_ax.set_xlabel(f"wall seconds per simulated second ({threads} thread{'s' if threads > 1 else ''})")
    cost_ax.set_ylabel("RMS deviation from the reference, mean over the frames (mm)")
    cost_ax.set_title(f"{resolution}x{resolution} drape: cost against deviation")
    time_ax.set_yscale("symlog", linthresh=0.01)
    time_ax.set_xlabel("simulated time (s)")
    time_ax.set_ylabel("RMS deviation from the reference (mm)")
    time_ax.set_title("deviation over time")
    time_ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "pareto.png", dpi=110)
    print(f"wrote {out / 'pareto.png'}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--weft", type=Path, default=ROOT / "build" / "release" / "src" / "weft")
    parser.add_argument("--resolution", type=int, default=64)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--peers", type=Path, help="bench/peers/run's results.csv")
    args = parser.parse_args()
    if not args.weft.is_file():
        fail(f"--weft {args.weft}: no such program (build it: cmake --build build/release --target weft)")
    if args.resolution < 2 or args.threads < 1 or args.runs < 1:
        fail("--resolution wants >= 2, --threads and --runs >= 1")
    if args.peers and not args.peers.is_file():
        fail(f"--peers {args.peers}: no such file")
    fps = json.loads(SCENE.read_text())["fps"]
    args.out.mkdir(parents=True, exist_ok=True)

    label, overrides = REFERENCE
    print(f"reference ({label}) ...", flush=True)
    _, summary = simulate(args.weft, args.out / "reference", args.resolution, args.threads, overrides)
    if summary["unconverged_steps"] > 0:
        print(f"warning: the reference has {int(summary['unconverged_steps'])} unconverged steps (largest residual "
              f"{summary['newton_residual_max']:.3g} m/s): its deviations are not those of a converged run")
    reference = read_pc2(args.out / "reference" / "cloth.pc2")

    costs = {label: [] for label, _ in CONFIGS}
    summaries = {}
    for run in range(args.runs):  # interleaved, so every configuration sees the same machine
        for k, (label, overrides) in enumerate(CONFIGS):
            cost, summaries[label] = simulate(args.weft, args.out / f"config{k}", args.resolution, args.threads,
                                              overrides)
            costs[label].append(cost)
            print(f"run {run + 1}/{args.runs} {label}: {costs[label][-1]:.2f} s per simulated second", flush=True)
    rows, per_frame = [], {}
    for k, (label, _) in enumerate(CONFIGS):
        series = deviations(read_pc2(args.out / f"config{k}" / "cloth.pc2"), reference)
        per_frame[label] = series
        rows.append({"label": label, "wall_per_sim_s": statistics.median(costs[label]),
                     "wall_runs": " ".join(f"{c:.3f}" for c in costs[label]),
                     "rms_mean_m": statistics.fmean(rms for rms, _ in series[1:]),
                     "rms_final_m": series[-1][0], "largest_m": max(largest for _, largest in series),
                     "newton": int(summaries[label]["newton_iterations"]["total"]),
                     "unconverged_steps": int(summaries[label]["unconverged_steps"])})
    with (args.out / "pareto.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    with (args.out / "deviation.csv").open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["label", "frame", "time", "rms_m", "largest_m"])
        for label, series in per_frame.items():
            for frame, (rms, largest) in enumerate(series):
                writer.writerow([label, frame, f"{frame / fps:.6f}", f"{rms:.6g}", f"{largest:.6g}"])
    print(f"{'configuration':40} {'s/sim s':>8} {'RMS mean':>9} {'RMS end':>8} {'largest':>8} {'Newton':>7}")
    for row in rows:
        print(f"{row['label']:40} {row['wall_per_sim_s']:8.2f} {1000 * row['rms_mean_m']:7.1f}mm "
              f"{1000 * row['rms_final_m']:6.1f}mm {1000 * row['largest_m']:6.0f}mm {row['newton']:7d}")
    peers = peer_costs(args.peers, args.resolution) if args.peers else {}
    for label, cost in peers.items():
        print(f"{label}: {cost:.2f} s per simulated second")
    plot(args.out, rows, per_frame, fps, peers, args.resolution, args.threads)


if __name__ == "__main__":
    main()
