#!/usr/bin/env python3
"""Writes the two tangled OBJ cloths of the untangling tests (tests/app/test_untangling.cpp):
folded_through.obj, a sheet folded over whose flap passes back through the sheet, and
pinched_tube.obj, an open tube whose top wall is pinched down through its bottom wall.
Run from this folder: python3 make_tangled_meshes.py"""
import math


def write_obj(name, rows, columns, point, comment, closed=False):
    # A (rows + 1) x (columns + 1) lattice, or (rows + 1) x columns closed around when `closed`.
    width = columns if closed else columns + 1
    with open(name, "w") as out:
        out.write(f"# {comment}\n# written by make_tangled_meshes.py\n")
        for i in range(rows + 1):
            for j in range(width):
                x, y, z = point(i, j)
                out.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        for i in range(rows):
            for j in range(columns):
                a = i * width + j + 1
                b = i * width + (j + 1) % width + 1
                c, d = a + width, b + width
                out.write(f"f {a} {b} {d}\nf {a} {d} {c}\n")


def folded_point(i, j, rows=60, columns=20, length=0.6, width=0.3, radius=0.02, slope=0.27):
    # Arc length u along the sheet: flat base, a half-turn fold, then a flap sloping back down.
    u = length * i / rows
    z = width * j / columns - 0.5 * width
    fold_start, fold_end = 0.3, 0.3 + math.pi * radius
    if u <= fold_start:
        return u - 0.15, 0.0, z
    if u <= fold_end:
        angle = (u - fold_start) / radius
        return fold_start - 0.15 + radius * math.sin(angle), radius * (1.0 - math.cos(angle)), z
    back = u - fold_end
    return fold_start - 0.15 - back, 2.0 * radius - slope * back, z


def tube_point(i, j, rows=40, columns=32, length=0.4, radius=0.04, depth=2.3):
    # Along x; around the axis by angle; the top strip (sin > 0.5) pressed down in the middle.
    x = length * i / rows - 0.5 * length
    angle = 2.0 * math.pi * j / columns
    s = math.sin(angle)
    bump = math.cos(math.pi * x / 0.16) ** 2 if abs(x) < 0.08 else 0.0
    press = depth * radius * bump * max(0.0, (s - 0.5) / 0.5) ** 2
    return x, radius * s - press, radius * math.cos(angle)


if __name__ == "__main__":
    write_obj("folded_through.obj", 60, 20, folded_point,
              "a 0.6 x 0.3 m sheet folded over at a 2 cm radius; its flap crosses the sheet and ends 2.4 cm below it")
    write_obj("pinched_tube.obj", 40, 32, tube_point,
              "an open tube, radius 4 cm, 0.4 m long; its top wall is pressed 1.2 cm through its bottom wall",
              closed=True)
