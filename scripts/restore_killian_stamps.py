#!/usr/bin/python3
"""Writes a copy of the MIT Killian Court log with scan stamps restored from its relations.

The only copy in ../shared/data (mit-killian.synthetic_time.clf) lost the original stamps: its
17480 FLASER lines carry 1e9 + i * 0.1 s, so mit-killian.relations (original stamps) cannot be
matched. The relations' 3838 stamps sit on the laser's period (about 0.4386 s): the gap between
two consecutive relation stamps, divided by the period and rounded, is the number of scans
between them. That gives every relation stamp a scan index up to one common offset, chosen here
as the offset whose scan pairs, placed by the relations' own relative poses, overlap best (mean
squared nearest-point distance over the short relations). Scans between two relation stamps get
interpolated stamps. Nothing else in the log changes.

Usage: restore_killian_stamps.py SHARED_DATA_DIR OUT.clf
"""
import bisect
import math
import sys

PERIOD_S = 0.4386       # the laser's period, from the relation stamps' gaps
OFFSETS = range(10, 31)  # candidate index offsets of the first relation stamp
CELL_M = 0.2            # grid cell for the nearest-point search
CAP_M2 = 0.01           # squared distances are capped at (0.1 m)^2


def read_log(path):
    lines = open(path).read().splitlines()
    scans = []
    for line in lines:
        if not line.startswith("FLASER"):
            continue
        fields = line.split()
        n = int(fields[1])
        ranges = [float(r) for r in fields[2:2 + n]]
        # CARMEN's FLASER convention: n beams from -90 deg, pi / n apart.
        scans.append([(r * math.cos(-math.pi / 2 + i * math.pi / n),
                       r * math.sin(-math.pi / 2 + i * math.pi / n))
                      for i, r in enumerate(ranges) if 0.1 < r < 40.0])
    return lines, scans


def read_relations(path):
    relations = []
    for line in open(path):
        f = line.split()
        if len(f) >= 8:
            relations.append((float(f[0]), float(f[1]), float(f[2]), float(f[3]), float(f[7])))
    return relations


def stamp_indices(relations):
    stamps = sorted({r[0] for r in relations} | {r[1] for r in relations})
    index = {stamps[0]: 0}
    for a, b in zip(stamps, stamps[1:]):
        index[b] = index[a] + round((b - a) / PERIOD_S)
    return index


class Grid:
    def __init__(self, points):
        self.cells = {}
        for x, y in points:
            self.cells.setdefault((math.floor(x / CELL_M), math.floor(y / CELL_M)), []).append((x, y))

    def nearest_sq(self, x, y):
        cx, cy = math.floor(x / CELL_M), math.floor(y / CELL_M)
        best = CAP_M2
        for ax in (cx - 1, cx, cx + 1):
            for ay in (cy - 1, cy, cy + 1):
                for px, py in self.cells.get((ax, ay), ()):
                    best = min(best, (px - x) ** 2 + (py - y) ** 2)
        return best


def overlap_cost(scans, grids, i, j, relation):
    """Mean capped squared distance of scan j's points, placed by the relation, to scan i."""
    if i not in grids:
        grids[i] = Grid(scans[i])
    _, _, dx, dy, dtheta = relation
    c, s = math.cos(dtheta), math.sin(dtheta)
    points = scans[j]
    total = sum(grids[i].nearest_sq(c * x - s * y + dx, s * x + c * y + dy) for x, y in points)
    return total / max(1, len(points))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    data, out_path = sys.argv[1], sys.argv[2]
    lines, scans = read_log(data + "/mit-killian/mit-killian.synthetic_time.clf")
    relations = read_relations(data + "/mit-killian/mit-killian.relations")
    index = stamp_indices(relations)
    short = sorted((r for r in relations if abs(r[1] - r[0]) < 3.0), key=lambda r: r[0])[::8]
    grids = {}
    costs = []
    for offset in OFFSETS:
        total, count = 0.0, 0
        for r in short:
            i, j = index[r[0]] + offset, index[r[1]] + offset
            if 0 <= i < len(scans) and 0 <= j < len(scans):
                total += overlap_cost(scans, grids, i, j, r)
                count += 1
        costs.append((total / max(1, count), offset))
    costs.sort()
    offset = costs[0][1]
    print("restore_killian_stamps: offset %d (mean squared distance %.5f m^2; next best %d: %.5f)"
          % (offset, costs[0][0], costs[1][1], costs[1][0]))
    known = {k + offset: t for t, k in index.items()}
    if min(known) < 0 or max(known) >= len(scans):
        sys.exit("restore_killian_stamps: relation stamps fall outside the log's scans")
    ids = sorted(known)

    def stamp(i):
        if i in known:
            return known[i]
        if i < ids[0]:
            return known[ids[0]] - (ids[0] - i) * PERIOD_S
        if i > ids[-1]:
            return known[ids[-1]] + (i - ids[-1]) * PERIOD_S
        k = bisect.bisect(ids, i)
        a, b = ids[k - 1], ids[k]
        return known[a] + (known[b] - known[a]) * (i - a) / (b - a)

    first = stamp(0)
    scan = 0
    with open(out_path, "w") as out:
        out.write("# MIT Killian Court with scan stamps restored from mit-killian.relations "
                  "(scripts/restore_killian_stamps.py, offset %d)\n" % offset)
        for line in lines:
            if not line.startswith("FLASER"):
                out.write(line + "\n")
                continue
            fields = line.split()
            t = stamp(scan)
            # FLASER ... timestamp hostname logger_timestamp
            fields[-3] = "%.6f" % t
            fields[-1] = "%.6f" % (t - first)
            out.write(" ".join(fields) + "\n")
            scan += 1
    print("restore_killian_stamps: %d scans, %d with a relation stamp, %.1f s, wrote %s"
          % (scan, len(known), stamp(scan - 1) - first, out_path))


if __name__ == "__main__":
    main()
