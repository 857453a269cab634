#!/usr/bin/env python3
"""Position RMSE [m] of an estimated trajectory against a true one, both `stamp x y theta` per
line, matched by stamp (to the millisecond). With --rigid, after the rotation and translation
that best fit the estimate onto the truth (least squares, no scale): what is left is the map's
shape, not where it was anchored. Usage: trajectory_rmse.py [--rigid] ESTIMATE TRUTH"""
import math
import sys


def poses(path):
    out = {}
    for line in open(path):
        fields = line.split()
        if len(fields) >= 4 and not line.startswith("#"):
            out[round(float(fields[0]), 3)] = (float(fields[1]), float(fields[2]))
    return out


def _matched(estimate_path, truth_path):
    est, truth = poses(estimate_path), poses(truth_path)
    common = sorted(t for t in est if t in truth)
    return [est[t] for t in common], [truth[t] for t in common]


def _rms(a, b):
    return math.sqrt(sum((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2
                         for p, q in zip(a, b)) / max(1, len(a)))


def rmse(estimate_path, truth_path):
    return _rms(*_matched(estimate_path, truth_path))


def rigid_rmse(estimate_path, truth_path):
    est, truth = _matched(estimate_path, truth_path)
    if not est:
        return 0.0
    n = len(est)
    ex, ey = sum(p[0] for p in est) / n, sum(p[1] for p in est) / n
    tx, ty = sum(p[0] for p in truth) / n, sum(p[1] for p in truth) / n
    # The rotation maximising sum <R a, b> over the centred points: atan2(sum a x b, sum a . b).
    dot = cross = 0.0
    for p, q in zip(est, truth):
        ax, ay, bx, by = p[0] - ex, p[1] - ey, q[0] - tx, q[1] - ty
        dot += ax * bx + ay * by
        cross += ax * by - ay * bx
    a = math.atan2(cross, dot)
    c, s = math.cos(a), math.sin(a)
    moved = [(c * (p[0] - ex) - s * (p[1] - ey) + tx, s * (p[0] - ex) + c * (p[1] - ey) + ty)
             for p in est]
    return _rms(moved, truth)


if __name__ == "__main__":
    args = sys.argv[1:]
    rigid = "--rigid" in args
    args = [a for a in args if a != "--rigid"]
    if len(args) != 2:
        sys.exit(__doc__)
    print("%.4f" % (rigid_rmse if rigid else rmse)(args[0], args[1]))
