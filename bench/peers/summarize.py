#!/usr/bin/python3
"""Summarises a peer benchmark folder written by bench/peers/run.

    /usr/bin/python3 bench/peers/summarize.py OUT [--no-plots]

Reads OUT/runs/*/ (run.txt, the simulator's output, check.txt) and writes
  OUT/results.csv           one row per simulator x N x threads x run
  OUT/results.md            medians per simulator x threads x N, and Weft's speed-ups
  OUT/time_vs_vertices.png  log-log wall seconds per simulated second against vertices
  OUT/final_frames_64.png   every simulator's final frame at N = 64, same camera
Can be rerun on a partial folder (an interrupted run).
"""
import csv
import math
import statistics
import sys
from pathlib import Path

SIMULATORS = ("weft", "weft_fast", "bullet", "blender")  # weft_fast: scenes/drape_sphere_fast.json
WEFT_TIERS = ("weft", "weft_fast")
SPHERE_RADIUS = 0.5

CSV_COLUMNS = ("simulator", "threads", "N", "run", "status", "exit_code", "vertices", "triangles",
               "steps", "simulated_s", "wall_s", "wall_per_sim_s", "ms_per_step", "peak_rss_mb",
               "min_y", "max_y", "inside_1cm", "inside_any", "max_depth", "intersecting_pairs",
               "load_before")


def key_values(line):
    """{key: value} of the `key=value` words of a line (other words are ignored)."""
    return dict(word.split("=", 1) for word in line.split() if "=" in word)


def last_line_starting(path, prefix):
    if not path.exists():
        return None
    lines = [line for line in path.read_text(errors="replace").splitlines() if line.startswith(prefix)]
    return lines[-1] if lines else None


def weft_stepping(recording):
    """Stepping figures of a Weft recording: the step_ms column (World::step, without start-up
    and without writing frames) summed over the simulated frames."""
    stats = recording / "stats.csv"
    if not stats.exists():
        return {}
    with stats.open() as file:
        rows = [row for row in csv.DictReader(file) if int(row["frame"]) > 0]
    if not rows:
        return {}
    step_ms = sum(float(row["step_ms"]) for row in rows)
    steps = sum(int(float(row["steps"])) for row in rows)
    return {"steps": steps, "simulated_s": float(rows[-1]["time"]), "wall_s": step_ms / 1e3}


def harness_stepping(stdout):
    """Stepping figures from a harness's `result` line (Bullet, Blender)."""
    line = last_line_starting(stdout, "result ")
    if line is None:
        return {}
    fields = key_values(line)
    return {"steps": int(fields["steps"]), "simulated_s": float(fields["simulated_s"]),
            "wall_s": float(fields["wall_s"])}


def read_run(folder):
    """One results.csv row from a run folder."""
    row = dict.fromkeys(CSV_COLUMNS, "")
    run = key_values((folder / "run.txt").read_text())
    row.update({key: run.get(key, "") for key in ("simulator", "threads", "N", "run", "status", "exit_code",
                                                  "load_before")})
    if run.get("peak_rss_kb"):
        row["peak_rss_mb"] = round(float(run["peak_rss_kb"]) / 1024.0, 1)
    if row["status"] != "ok":
        return row
    if row["simulator"] in WEFT_TIERS:
        stepping = weft_stepping(folder / "weft")
    else:
        stepping = harness_stepping(folder / "stdout.txt")
    if stepping:
        row.update(stepping)
        row["wall_per_sim_s"] = stepping["wall_s"] / stepping["simulated_s"]
        row["ms_per_step"] = 1e3 * stepping["wall_s"] / stepping["steps"]
    check = last_line_starting(folder / "check.txt", "vertices=")
    if check:
        row.update({key: value for key, value in key_values(check).items() if key in row})
    return row


def collect(out):
    rows = [read_run(folder) for folder in sorted((out / "runs").glob("*/")) if (folder / "run.txt").exists()]
    order = {name: rank for rank, name in enumerate(SIMULATORS)}
    rows.sort(key=lambda r: (int(r["N"]), order.get(r["simulator"], 9), int(r["threads"]), int(r["run"])))
    return rows


def write_csv(path, rows):
    with path.open("w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)


def median_of(rows, column):
    values = [float(r[column]) for r in rows if r[column] not in ("", None)]
    return statistics.median(values) if values else None


def group_medians(rows):
    """{(simulator, threads, N): medians over the runs that finished}, in the rows' order."""
    groups = {}
    for row in rows:
        groups.setdefault((row["simulator"], int(row["threads"]), int(row["N"])), []).append(row)
    medians = {}
    for key, runs in groups.items():
        finished = [r for r in runs if r["status"] == "ok" and r["wall_s"] != ""]
        statuses = sorted({r["status"] for r in runs if r["status"] != "ok"})
        summary = {"runs": len(runs), "finished": len(finished), "not_ok": "/".join(statuses)}
        for column in ("vertices", "steps", "wall_per_sim_s", "ms_per_step", "peak_rss_mb", "min_y", "max_y",
                       "inside_1cm", "inside_any", "intersecting_pairs"):
            summary[column] = median_of(finished, column)
        medians[key] = summary
    return medians


def speed_up(medians, key, tier="weft"):
    """A Weft tier's speed-up over a peer's configuration: the tier at the same thread count
    (Bullet runs with 1 thread, Blender with the counts asked for)."""
    simulator, threads, n = key
    weft = medians.get((tier, threads, n))
    peer = medians[key]
    if simulator in WEFT_TIERS or not weft or not weft["wall_per_sim_s"] or not peer["wall_per_sim_s"]:
        return None
    return peer["wall_per_sim_s"] / weft["wall_per_sim_s"]


def number(value, digits=3):
    if value is None:
        return "—"
    return f"{value:.{digits}f}"


def write_markdown(path, medians, machine):
    lines = ["# Weft vs Bullet and Blender: cloth dropped onto a sphere, 1 simulated second", ""]
    if machine:
        lines += ["```", machine.strip(), "```", ""]
    lines += ["Medians over the runs that finished. Wall time covers stepping only (no start-up, scene "
              "build or writing). Heights, vertices inside the sphere and intersecting triangle pairs are "
              "measured on each final mesh by `weft_check_mesh`. Speed-up: the peer's wall time over "
              "Weft's at the same thread count (weft: the drape as shipped; weft_fast: Weft's fast tier, "
              "scenes/drape_sphere_fast.json, when it ran).", "",
              "| simulator | threads | N | vertices | runs ok | wall s / sim s | ms / step (steps) | "
              "peak RSS MB | final min height | final max height | verts inside sphere >1 cm (any) | "
              "intersecting pairs | Weft speed-up | fast tier speed-up |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for key, m in medians.items():
        simulator, threads, n = key
        if m["finished"] == 0:
            wall = m["not_ok"] or "failed"
        else:
            wall = number(m["wall_per_sim_s"])
        ok = f"{m['finished']}/{m['runs']}" + (f" ({m['not_ok']})" if m["not_ok"] else "")
        up = speed_up(medians, key)
        fast_up = speed_up(medians, key, "weft_fast")
        lines.append(
            f"| {simulator} | {threads} | {n} | {number(m['vertices'], 0)} | {ok} | {wall} | "
            f"{number(m['ms_per_step'])} ({number(m['steps'], 0)}) | {number(m['peak_rss_mb'], 0)} | "
            f"{number(m['min_y'])} | {number(m['max_y'])} | {number(m['inside_1cm'], 0)} "
            f"({number(m['inside_any'], 0)}) | {number(m['intersecting_pairs'], 0)} | "
            f"{'—' if up is None else f'{up:.2f}x'} | {'—' if fast_up is None else f'{fast_up:.2f}x'} |")

    # The headline pairs: Weft 1 thread vs Bullet and Blender 1 thread, Weft 2 threads vs Blender 2.
    pairs = (("Weft 1 thread vs Bullet (1 thread)", ("bullet", 1)),
             ("Weft 1 thread vs Blender 1 thread", ("blender", 1)),
             ("Weft 2 threads vs Blender 2 threads", ("blender", 2)))
    sizes = sorted({n for _, _, n in medians})
    lines += ["", "Weft's speed-up (peer wall time / Weft wall time; above 1: Weft is faster):", "",
              "| comparison | " + " | ".join(f"N = {n}" for n in sizes) + " |",
              "|---|" + "---:|" * len(sizes)]
    tiers = [tier for tier in WEFT_TIERS if any(key[0] == tier for key in medians)]
    for tier in tiers:
        for label, (simulator, threads) in pairs:
            cells = []
            for n in sizes:
                key = (simulator, threads, n)
                up = speed_up(medians, key, tier) if key in medians else None
                cells.append("—" if up is None else f"{up:.2f}x")
            name = label if tier == "weft" else label.replace("Weft", "Weft's fast tier", 1)
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
    path.write_text("\n".join(lines) + "\n")


def fitted_exponent(vertices, seconds):
    """Slope of log(seconds) against log(vertices) by least squares; None below two points."""
    if len(vertices) < 2:
        return None
    xs = [math.log(v) for v in vertices]
    ys = [math.log(s) for s in seconds]
    x_mean, y_mean = statistics.fmean(xs), statistics.fmean(ys)
    spread = sum((x - x_mean) ** 2 for x in xs)
    return sum((x - x_mean) * (y - y_mean) for x, y in zip(xs, ys)) / spread if spread > 0 else None


def plot_time_vs_vertices(path, medians, pyplot):
    lines = {}
    for (simulator, threads, n), m in medians.items():
        if m["wall_per_sim_s"] and m["vertices"]:
            lines.setdefault((simulator, threads), []).append((m["vertices"], m["wall_per_sim_s"]))
    figure, axes = pyplot.subplots(figsize=(7, 5))
    colours = {"weft": "tab:blue", "weft_fast": "tab:purple", "bullet": "tab:orange", "blender": "tab:green"}
    for (simulator, threads), points in sorted(lines.items()):
        points.sort()
        vertices = [p[0] for p in points]
        seconds = [p[1] for p in points]
        exponent = fitted_exponent(vertices, seconds)
        label = f"{simulator}, {threads} thread{'s' if threads > 1 else ''}"
        if exponent is not None:
            label += f" (time ~ vertices^{exponent:.2f})"
        axes.plot(vertices, seconds, marker="o", color=colours.get(simulator, "grey"),
                  linestyle="-" if threads > 1 else "--", label=label)
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("cloth vertices")
    axes.set_ylabel("wall seconds per simulated second")
    axes.set_title("Drape on a sphere, self collision on (medians)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    pyplot.close(figure)


def read_obj(path):
    """Vertices and triangles (0-based) of a triangle OBJ; polygons are fanned."""
    vertices, triangles = [], []
    for line in path.read_text().splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            vertices.append(tuple(float(w) for w in words[1:4]))
        elif words[0] == "f":
            corners = [int(w.split("/")[0]) - 1 for w in words[1:]]
            triangles += [(corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1)]
    return vertices, triangles


def plot_final_frames(path, rows, n, pyplot):
    """Each simulator's final frame at N = n: a 3-D view (orthographic, same camera) and a side
    view, the sphere drawn in both. Y-up meshes are drawn with matplotlib's Z up."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    chosen = {}
    for row in rows:
        folder_key = (row["simulator"], row["threads"], row["N"], row["run"])
        if int(row["N"]) == n and row["status"] == "ok" and row["simulator"] not in chosen:
            chosen[row["simulator"]] = folder_key
    if not chosen:
        return False
    figure = pyplot.figure(figsize=(4.2 * len(chosen), 8))
    light = (0.3, -0.5, 0.8)
    light_norm = math.sqrt(sum(c * c for c in light))
    for column, (simulator, (_, threads, _, run)) in enumerate(chosen.items()):
        folder = path.parent / "runs" / f"{simulator}-t{threads}-n{n}-r{run}"
        vertices, triangles = read_obj(folder / "final.obj")
        # Y up -> Z up: (x, y, z) -> (x, -z, y), a rotation.
        points = [(x, -z, y) for x, y, z in vertices]

        axes = figure.add_subplot(2, len(chosen), column + 1, projection="3d", proj_type="ortho")
        axes.computed_zorder = False
        draw_sphere(axes)
        polygons, shades = [], []
        for a, b, c in triangles:
            pa, pb, pc = points[a], points[b], points[c]
            u = [pb[k] - pa[k] for k in range(3)]
            v = [pc[k] - pa[k] for k in range(3)]
            normal = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
            length = math.sqrt(sum(c * c for c in normal)) or 1.0
            # Two-sided lighting: the cloth has no outside.
            shade = abs(sum(normal[k] * light[k] for k in range(3))) / (length * light_norm)
            polygons.append((pa, pb, pc))
            shades.append((0.25 + 0.6 * shade, 0.45 + 0.45 * shade, 0.85 * (0.5 + 0.5 * shade)))
        axes.add_collection3d(Poly3DCollection(polygons, facecolors=shades, edgecolors="none", zorder=2))
        axes.set_xlim(-1, 1)
        axes.set_ylim(-1, 1)
        axes.set_zlim(-0.8, 1.2)
        axes.set_box_aspect((1, 1, 1))
        axes.view_init(elev=25, azim=-60)
        axes.set_title(f"{simulator} ({threads} thread{'s' if int(threads) > 1 else ''}), N = {n}")

        side = figure.add_subplot(2, len(chosen), len(chosen) + column + 1)
        side.add_patch(pyplot.Circle((0, 0), SPHERE_RADIUS, color="0.75", zorder=1))
        side.scatter([p[0] for p in vertices], [p[1] for p in vertices], s=0.3, color="tab:blue", zorder=2)
        side.set_xlim(-1.1, 1.1)
        side.set_ylim(-0.9, 1.1)
        side.set_aspect("equal")
        side.set_xlabel("x (m)")
        side.set_ylabel("height y (m)")
        side.set_title("side view (all vertices)", fontsize=9)
        side.grid(True, alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    pyplot.close(figure)
    return True


def draw_sphere(axes, segments=32, rings=16):
    """The collider as grey quads, drawn before (below) the cloth."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    def point(i, j):
        u, v = 2 * math.pi * i / segments, math.pi * j / rings
        return (SPHERE_RADIUS * math.cos(u) * math.sin(v), SPHERE_RADIUS * math.sin(u) * math.sin(v),
                SPHERE_RADIUS * math.cos(v))

    quads = [(point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1))
             for i in range(segments) for j in range(rings)]
    # Lit from above: brighter towards the top.
    shades = [str(round(0.45 + 0.35 * (q[0][2] + q[2][2]) / (2 * SPHERE_RADIUS), 3)) for q in quads]
    axes.add_collection3d(Poly3DCollection(quads, facecolors=shades, edgecolors="none", zorder=1))


def main():
    arguments = sys.argv[1:]
    plots = "--no-plots" not in arguments
    arguments = [a for a in arguments if a != "--no-plots"]
    if len(arguments) != 1:
        sys.stderr.write("usage: summarize.py OUT [--no-plots]\n")
        return 2
    out = Path(arguments[0])
    if not (out / "runs").is_dir():
        sys.stderr.write(f"summarize.py: {out / 'runs'}: no runs to summarise\n")
        return 2
    rows = collect(out)
    write_csv(out / "results.csv", rows)
    medians = group_medians(rows)
    machine_file = out / "machine.txt"
    write_markdown(out / "results.md", medians, machine_file.read_text() if machine_file.exists() else "")
    print((out / "results.md").read_text())
    if plots:
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib import pyplot

        plot_time_vs_vertices(out / "time_vs_vertices.png", medians, pyplot)
        if not plot_final_frames(out / "final_frames_64.png", rows, 64, pyplot):
            sys.stderr.write("summarize.py: no finished run at N = 64, final_frames_64.png not drawn\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
