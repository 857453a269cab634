#!/usr/bin/python3
"""Turns the GMapping-corrected CARMEN logs into mapping inputs with drifting odometry.

../shared/data/radish-gfs-corrected holds thirteen buildings and campuses (180, 181, 360 and 361
beams) as GMapping kept them: keyframe scans only (0.5-1 m and up to 0.6 rad apart, far sparser
than a laser's rate), and every pose in them is GMapping's corrected estimate, not odometry. So
they say nothing about a mapper as they are. This script writes, per log:

  NAME.log        FLASER lines only: the same scans, stamped 1 s apart, with an odometry made
                  from the corrected poses' steps by a drifting, noisy model (translation 3 % long,
                  turns 3 % too far plus 0.01 rad per metre driven, Gaussian noise of 1 % of the
                  step and 0.002 rad, fixed seed): a robot whose wheels are badly calibrated;
  NAME.relations  reference relations in the Freiburg format from the corrected poses (each scan
                  to the next, the third and the tenth after it, and one random other scan).

The reference is GMapping's map, not ground truth: errors of a few centimetres mean agreement
with it, not accuracy. The logs test what the Freiburg bags cannot: other buildings and lasers,
and registration over large steps.

Usage: keyframe_logs.py SHARED_DATA_DIR OUT_DIR [NAME ...]   (default: every *-corrected.log)
"""
import math
import os
import random
import sys

SCALE = 1.03            # odometry's steps and turns are this much too long
DRIFT_RAD_PER_M = 0.01  # ... and it turns this much per metre driven
NOISE_PER_M = 0.01      # Gaussian noise of each step: this fraction of the step
NOISE_RAD = 0.002       # ... and this (plus 1 % of the turn) in heading
PERIOD_S = 1.0          # stamps of consecutive scans
SEED = 7


def read_scans(path):
    scans = []
    for line in open(path):
        fields = line.split()
        if not fields or fields[0] != "FLASER":
            continue
        n = int(fields[1])
        ranges = fields[2:2 + n]
        pose = tuple(float(v) for v in fields[2 + n:5 + n])
        scans.append((ranges, pose))
    return scans


def between(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    dth = math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2]))
    return (c * dx + s * dy, -s * dx + c * dy, dth)


def compose(a, d):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * d[0] - s * d[1], a[1] + s * d[0] + c * d[1], a[2] + d[2])


def drifting_odometry(poses, rng):
    odometry = [(0.0, 0.0, 0.0)]
    for previous, pose in zip(poses, poses[1:]):
        dx, dy, dth = between(previous, pose)
        dist = math.hypot(dx, dy)
        step = (SCALE * dx + rng.gauss(0.0, NOISE_PER_M * dist),
                SCALE * dy + rng.gauss(0.0, NOISE_PER_M * dist),
                SCALE * dth + DRIFT_RAD_PER_M * dist + rng.gauss(0.0, 0.01 * abs(dth) + NOISE_RAD))
        odometry.append(compose(odometry[-1], step))
    return odometry


def write_log(path, scans, odometry):
    with open(path, "w") as out:
        for i, ((ranges, _), odom) in enumerate(zip(scans, odometry)):
            stamp = 1000.0 + i * PERIOD_S
            pose = "%.6f %.6f %.6f" % odom
            # FLASER n ranges laser_pose odom_pose stamp host logger_stamp: the same pose twice
            # (the corrected logs carry no laser offset).
            out.write("FLASER %d %s %s %s %.6f keyframes %.6f\n" %
                      (len(ranges), " ".join(ranges), pose, pose, stamp, stamp))


def write_relations(path, scans, rng):
    n = len(scans)
    with open(path, "w") as out:
        for i in range(n):
            for j in (i + 1, i + 3, i + 10, rng.randrange(n)):
                if j >= n or j == i:
                    continue
                dx, dy, dth = between(scans[i][1], scans[j][1])
                out.write("%.6f %.6f %.6f %.6f 0 0 0 %.6f\n" %
                          (1000.0 + i * PERIOD_S, 1000.0 + j * PERIOD_S, dx, dy, dth))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    source = os.path.join(sys.argv[1], "radish-gfs-corrected")
    out_dir = sys.argv[2]
    known = sorted(f[:-len("-corrected.log")] for f in os.listdir(source)
                   if f.endswith("-corrected.log"))
    names = sys.argv[3:] or known
    unknown = [name for name in names if name not in known]
    if unknown:
        sys.exit("keyframe_logs.py: no log named %s in %s (there are: %s)" %
                 (", ".join(unknown), source, " ".join(known)))
    os.makedirs(out_dir, exist_ok=True)
    for name in names:
        scans = read_scans(os.path.join(source, name + "-corrected.log"))
        if len(scans) < 2:
            sys.exit("keyframe_logs.py: %s has fewer than two FLASER scans" % name)
        rng = random.Random(SEED)
        write_log(os.path.join(out_dir, name + ".log"), scans,
                  drifting_odometry([pose for _, pose in scans], rng))
        write_relations(os.path.join(out_dir, name + ".relations"), scans, rng)
        print("%s: %d scans" % (name, len(scans)))


if __name__ == "__main__":
    main()
