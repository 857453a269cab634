#!/usr/bin/env bash
# Benchmark with other lasers: the simulated care-home patrol (430 s, people walking) recorded
# with a 181-beam laser over 180 deg at the base's centre, interlaced (every other scan starts
# half a beam later) and plain, for seeds 1..N (each seed: other people, other odometry noise).
# Maps every bag with the default configuration (or --config FILE) and prints per seed the
# trajectory's position RMSE against the truth after a rigid alignment (the map's shape) and
# without one (where it was anchored too), and the means; writes output/bench_lasers.json.
# The bags are made once and kept in output/bench_lasers/sim. Figures are measured, never
# asserted.
# Usage: scripts/bench_lasers.sh [--no-build] [--config FILE.yaml] [--seeds N]   (default 12)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench_lasers"

BUILD=1
CONFIG="$ROOT/config/mapping.yaml"
SEEDS=12
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) BUILD=0 ;;
    --config) CONFIG="$(realpath "${2:?--config needs a file}")"; shift ;;
    --seeds) SEEDS="${2:?--seeds needs a count}"; shift ;;
    *) echo "bench_lasers.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
  shift
done
[[ "$SEEDS" =~ ^[1-9][0-9]*$ ]] || { echo "bench_lasers.sh: --seeds must be a positive count" >&2; exit 2; }
[ $BUILD -eq 0 ] || bench_build
mkdir -p "$OUT/sim"

LASERS=(interlaced plain)
for laser in "${LASERS[@]}"; do
  flags=(--beams 181 --fov-deg 180 --laser-x 0)
  [ "$laser" = interlaced ] && flags+=(--interlaced)
  for seed in $(seq 1 "$SEEDS"); do
    sim="$OUT/sim/${laser}_$seed"
    if [ ! -s "$sim/session_1_truth_trajectory.txt" ]; then
      mkdir -p "$sim"
      "$BIN/simulate_world" --world "$ROOT/config/worlds/care_home.yaml" --out "$sim" \
        --seed "$seed" --duration 430 "${flags[@]}" > /dev/null
    fi
    "$BIN/offline_mapper" --bag "$sim/session_1.bag" --config "$CONFIG" \
      --trajectory "$OUT/$laser.$seed.trajectory.txt" --stats "$OUT/$laser.$seed.stats.json" \
      2> "$OUT/$laser.$seed.log" > /dev/null
  done
done

/usr/bin/python3 - "$ROOT/scripts" "$OUT" "$SEEDS" "${LASERS[@]}" <<'PY'
import json, os, sys
sys.path.insert(0, sys.argv[1])
from trajectory_rmse import rigid_rmse, rmse
out, seeds, lasers = sys.argv[2], int(sys.argv[3]), sys.argv[4:]
rows = []
print("| seed | " + " | ".join("%s: rigid (unaligned) [m]" % l for l in lasers) + " |")
print("|---|" + "---|" * len(lasers))
for seed in range(1, seeds + 1):
    cells = []
    for laser in lasers:
        truth = os.path.join(out, "sim", "%s_%d" % (laser, seed), "session_1_truth_trajectory.txt")
        estimate = os.path.join(out, "%s.%d.trajectory.txt" % (laser, seed))
        stats = json.load(open(os.path.join(out, "%s.%d.stats.json" % (laser, seed))))
        row = {"laser": laser, "seed": seed, "rigid_rmse_m": rigid_rmse(estimate, truth),
               "rmse_m": rmse(estimate, truth),
               "tracker_failures": stats["counters"].get("tracker_failures", 0)}
        rows.append(row)
        cells.append("%.4f (%.3f)" % (row["rigid_rmse_m"], row["rmse_m"]))
    print("| %d | %s |" % (seed, " | ".join(cells)))
print()
for laser in lasers:
    mine = [r for r in rows if r["laser"] == laser]
    rigid = [r["rigid_rmse_m"] for r in mine]
    print("%s: mean rigid RMSE %.4f m (%.4f-%.4f), mean unaligned %.3f m, tracker failures %d"
          % (laser, sum(rigid) / len(rigid), min(rigid), max(rigid),
             sum(r["rmse_m"] for r in mine) / len(mine), sum(r["tracker_failures"] for r in mine)))
path = os.path.join(os.path.dirname(out), "bench_lasers.json")
json.dump(rows, open(path, "w"), indent=2)
print("bench_lasers.sh: wrote %s" % path)
PY
