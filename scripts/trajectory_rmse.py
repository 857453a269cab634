#!/usr/bin/env python3
"""Position RMSE [m] of an estimated trajectory against a true one, both `stamp x y theta` per
line, matched by stamp (to the millisecond). Usage: trajectory_rmse.py ESTIMATE TRUTH"""
import math
import sys


def poses(path):
    out = {}
    for line in open(path):
        fields = line.split()
        if len(fields) >= 4 and not line.startswith("#"):
            out[round(float(fields[0]), 3)] = (float(fields[1]), float(fields[2]))
    return out


def rmse(estimate_path, truth_path):
    est, truth = poses(estimate_path), poses(truth_path)
    common = [t for t in est if t in truth]
    return math.sqrt(sum((est[t][0] - truth[t][0]) ** 2 + (est[t][1] - truth[t][1]) ** 2
                         for t in common) / max(1, len(common)))


if __name__ == "__main__":
    print("%.4f" % rmse(sys.argv[1], sys.argv[2]))
