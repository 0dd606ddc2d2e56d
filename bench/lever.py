#!/usr/bin/python3
"""A solver lever measured against the spread of the scene's own chaos.

    /usr/bin/python3 bench/lever.py --out out/lever --candidate 'collision.collider_contact_ratio=0'
        [--candidate 'path=value;path=value' ...] [--scene scenes/drape_sphere.json] [--starts 4]
        [--frames N] [--threads 1] [--weft build/release/src/weft]

A cloth that folds is chaotic: moving the drape's start by 1 micrometre changes its Newton
iterations over 30 frames by a few percent, so one run of a lever
against one run of the scene cannot resolve a change that size. This runs the scene as it is
(the baseline) and each candidate (one or more overrides, `;`-separated, as `weft --set` takes
them) from --starts starts: the scene's own and starts with cloth 0 moved by 1, 2, ...
micrometres along x, y, z in turn. The runs are interleaved (every configuration from one start,
then the next start), so that the machine's drift falls on all alike. Per configuration it prints
the median and the range over the starts of the Newton iterations, the CG iterations, the
unconverged steps and the seconds of stepping per simulated second (stats.csv's step_ms, as
bench/peers/run counts it), and whether the candidate's Newton range lies apart from the
baseline's. Writes OUT/lever.csv (one row per run). A benchmark, not a test: never run by ctest.
Timings are only comparable within one invocation on an otherwise idle machine.
"""
import argparse
import csv
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.dont_write_bytecode = True  # no __pycache__ left in the source tree
sys.path.insert(0, str(ROOT / "bench" / "peers"))
from summarize import weft_stepping  # noqa: E402  the cost as bench/peers/run counts it

MICROMETRE = 1e-6


def fail(message):
    print(f"bench/lever.py: {message}", file=sys.stderr)
    sys.exit(2)


def start_overrides(scene, start):
    """The overrides that move cloth 0 for start k (none for k = 0)."""
    if start == 0:
        return []
    cloths = scene.get("cloths") or []
    if not cloths:
        fail("the scene has no cloth to move")
    translation = list((cloths[0].get("transform") or {}).get("translation", [0.0, 0.0, 0.0]))
    translation[(start - 1) % 3] += MICROMETRE * ((start - 1) // 3 + 1)
    return [f"cloths.0.transform.translation=[{','.join(repr(float(c)) for c in translation)}]"]


def run(weft, scene_path, out_dir, threads, frames, overrides):
    """One headless run; returns its figures."""
    args = [str(weft), "--headless", str(scene_path), "--out", str(out_dir), "--quiet", "--threads", str(threads),
            "--fixed-threads"]
    if frames is not None:
        args += ["--frames", str(frames)]
    for override in overrides:
        args += ["--set", override]
    result = subprocess.run(args, capture_output=True, text=True)
    summary_path = out_dir / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    if result.returncode != 0 or summary.get("status") != "complete":
        fail(f"{' '.join(args)} exited {result.returncode}: {result.stderr.strip()[-400:]}")
    with (out_dir / "stats.csv").open() as f:
        cg = sum(int(float(row["linear_iterations"])) for row in csv.DictReader(f))
    stepping = weft_stepping(out_dir)
    return {"newton": int(summary["newton_iterations"]["total"]), "cg": cg,
            "unconverged": int(summary["unconverged_steps"]),
            "step_s_per_sim_s": stepping["wall_s"] / stepping["simulated_s"],
            "budget_error_j": summary.get("energy", {}).get("budget_error_max", float("nan"))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--candidate", action="append", required=True,
                        help="overrides as weft --set takes them, several separated by ';'")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes" / "drape_sphere.json")
    parser.add_argument("--starts", type=int, default=4)
    parser.add_argument("--frames", type=int)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--weft", type=Path, default=ROOT / "build" / "release" / "src" / "weft")
    args = parser.parse_args()
    if not args.weft.is_file():
        fail(f"--weft {args.weft}: no such program (build it: cmake --build build/release --target weft)")
    if not args.scene.is_file():
        fail(f"--scene {args.scene}: no such file")
    if args.starts < 2 or args.threads < 1 or (args.frames is not None and args.frames < 1):
        fail("--starts wants >= 2 (one start shows no spread), --threads and --frames >= 1")
    try:
        scene = json.loads(args.scene.read_text())
    except json.JSONDecodeError as error:
        fail(f"--scene {args.scene}: not JSON ({error})")
    configurations = [("baseline (the scene)", [])]
    for candidate in args.candidate:
        overrides = [part.strip() for part in candidate.split(";") if part.strip()]
        if not overrides or any("=" not in part for part in overrides):
            fail(f"--candidate {candidate!r}: expected path=value[;path=value...]")
        configurations.append((candidate, overrides))
    args.out.mkdir(parents=True, exist_ok=True)

    rows = []
    for start in range(args.starts):
        moved = start_overrides(scene, start)
        for k, (label, overrides) in enumerate(configurations):
            figures = run(args.weft, args.scene, args.out / f"config{k}_start{start}", args.threads, args.frames,
                          moved + overrides)
            rows.append({"configuration": label, "start": start, **figures})
            print(f"start {start} {label}: Newton {figures['newton']}, CG {figures['cg']}, "
                  f"unconverged {figures['unconverged']}, {figures['step_s_per_sim_s']:.2f} s per simulated second",
                  flush=True)
    with (args.out / "lever.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    def column(label, key):
        return [row[key] for row in rows if row["configuration"] == label]

    baseline = column(configurations[0][0], "newton")
    print(f"\n{'configuration':44} {'Newton median [range]':>24} {'CG median':>10} {'unconverged (most)':>19} "
          f"{'s/sim s':>8}")
    for label, _ in configurations:
        newton = column(label, "newton")
        spread = f"{statistics.median(newton):.0f} [{min(newton)}-{max(newton)}]"
        print(f"{label[:44]:44} {spread:>24} {statistics.median(column(label, 'cg')):>10.0f} "
              f"{max(column(label, 'unconverged')):>19} {statistics.median(column(label, 'step_s_per_sim_s')):>8.2f}")
    for label, _ in configurations[1:]:
        newton = column(label, "newton")
        ratio = statistics.median(newton) / statistics.median(baseline)
        apart = max(newton) < min(baseline) or min(newton) > max(baseline)
        print(f"{label}: Newton x{ratio:.3f} of the baseline's median; "
              + ("outside the baseline's range over the starts" if apart else
                 "within the baseline's range over the starts: not resolved from the chaos"))
    print(f"wrote {args.out / 'lever.csv'}")


if __name__ == "__main__":
    main()
