#!/usr/bin/env python3
"""Writes a pairs CSV for `nestwalk query overlap` (engine/geometry/box_pairs_csv.h), to time it.

Usage: make_box_pairs.py COUNT OUT.csv [SEED]

A mixture like a scene's equipment: 40% of the boxes turned about the vertical only, 20% axis
aligned, 40% turned anyhow; half extents log-uniform in [0.05, 3] m; box A at UTM-like map
coordinates (x ~ 5e5, y ~ 7e6 m), box B at a random offset of up to 0.6 x the sum of the half
diagonals (about half the pairs overlap). Numbers are printed with 17 significant digits, so the
doubles read back are the ones generated.
"""
import math
import random
import sys


def rotation(rng):
    kind = rng.random()
    if kind < 0.2:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]  # columns u, v, w
    if kind < 0.6:
        a = rng.uniform(0, 2 * math.pi)
        c, s = math.cos(a), math.sin(a)
        return [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
    w, x, y, z = (rng.gauss(0, 1) for _ in range(4))
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    m = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return [[m[r][c] for r in range(3)] for c in range(3)]  # columns


def main():
    count, out = int(sys.argv[1]), sys.argv[2]
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 20261126)
    cols = ["cx", "cy", "cz", "ux", "uy", "uz", "vx", "vy", "vz", "wx", "wy", "wz", "ex", "ey", "ez"]
    with open(out, "w") as f:
        f.write("id," + ",".join("a" + c for c in cols) + "," + ",".join("b" + c for c in cols) + "\n")
        for k in range(count):
            ea = [math.exp(rng.uniform(math.log(0.05), math.log(3))) for _ in range(3)]
            eb = [math.exp(rng.uniform(math.log(0.05), math.log(3))) for _ in range(3)]
            ca = [rng.uniform(5.0e5, 5.1e5), rng.uniform(7.0e6, 7.01e6), rng.uniform(100, 300)]
            reach = 0.6 * (math.sqrt(sum(e * e for e in ea)) + math.sqrt(sum(e * e for e in eb)))
            d = [rng.gauss(0, 1) for _ in range(3)]
            n = math.sqrt(sum(x * x for x in d)) or 1.0
            r = rng.uniform(0, 1) * reach
            cb = [ca[i] + d[i] / n * r for i in range(3)]
            fields = [f"p{k}"]
            for c, axes, e in ((ca, rotation(rng), ea), (cb, rotation(rng), eb)):
                fields += [repr(x) for x in c]
                fields += [repr(x) for col in axes for x in col]
                fields += [repr(x) for x in e]
            f.write(",".join(fields) + "\n")


if __name__ == "__main__":
    main()
