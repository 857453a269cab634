#!/usr/bin/env bash
# Long-run benchmark, STRANDS-like: HOURS hours (default 10) of simulated patrol of the care home
# (config/worlds/care_home.yaml, people walking), one bag, mapped hour by hour: each hour loads the
# map the previous hour saved and starts at the previous hour's last pose (offline_mapper --start
# / --end / --load-map / --initial-pose), as a robot that saves its map every hour would. Prints
# per hour the wall time, real-time factor, nodes, edges, map file size, peak RSS and trajectory
# RMSE against the simulator's truth, as a table and as output/bench_long.json, and the totals.
# Measured, never asserted. Usage: scripts/bench_long.sh [--no-build] [--no-maintenance] [HOURS]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench_long"
BUILD=1
HOURS=10
EXTRA=()
for arg in "$@"; do
  case "$arg" in
    --no-build) BUILD=0 ;;
    --no-maintenance) EXTRA+=(--no-maintenance) ;;
    [0-9]*) HOURS="$arg" ;;
    *) echo "bench_long.sh: unknown option '$arg'" >&2; exit 2 ;;
  esac
done
[ $BUILD -eq 0 ] || bench_build
rm -rf "$OUT"
mkdir -p "$OUT"
echo "bench_long.sh: simulating $HOURS h of patrol" >&2
sim_start=$(date +%s.%N)
"$BIN/simulate_world" --world "$ROOT/config/worlds/care_home.yaml" --out "$OUT/sim" --sessions 1 \
  --seed 1 --duration $((HOURS * 3600)) > "$OUT/simulate.log" 2>&1
sim_end=$(date +%s.%N)
previous=()
for h in $(seq 1 "$HOURS"); do
  "$BIN/offline_mapper" --bag "$OUT/sim/session_1.bag" --start $(((h - 1) * 3600)) \
    --end $((h * 3600)) "${previous[@]}" "${EXTRA[@]}" --save-map "$OUT/hour$h.ltmap" \
    --trajectory "$OUT/hour$h.trajectory.txt" --stats "$OUT/hour$h.stats.json" 2> "$OUT/hour$h.log"
  last=$(grep -v '^#' "$OUT/hour$h.trajectory.txt" | tail -n 1)
  pose=$(echo "$last" | awk '{printf "%.6f,%.6f,%.6f", $2, $3, $4}')
  previous=(--load-map "$OUT/hour$h.ltmap" --initial-pose "$pose")
  echo "bench_long.sh: hour $h done" >&2
done

/usr/bin/python3 - "$OUT" "$HOURS" "$sim_start" "$sim_end" "$ROOT/scripts" <<'PY'
import json, os, sys
out, hours = sys.argv[1], int(sys.argv[2])
sim_s = float(sys.argv[4]) - float(sys.argv[3])
sys.dont_write_bytecode = True
sys.path.insert(0, sys.argv[5])
from trajectory_rmse import rmse
truth = os.path.join(out, "sim", "session_1_truth_trajectory.txt")
rows = []
for h in range(1, hours + 1):
    s = json.load(open(os.path.join(out, "hour%d.stats.json" % h)))
    g = s["graph"]
    rows.append({"hour": h, "wall_s": s["wall_time_s"], "rtf": s["real_time_factor"],
                 "nodes": g["nodes"],
                 "edges": g["edges_odometry"] + g["edges_loop_closure"] + g["edges_condensed"],
                 "file_mb": os.path.getsize(os.path.join(out, "hour%d.ltmap" % h)) / 1e6,
                 "peak_rss_mb": s["peak_rss_mb"],
                 "rmse_m": rmse(os.path.join(out, "hour%d.trajectory.txt" % h), truth)})
print("| hour | wall [s] | real-time factor | nodes | edges | map file [MB] | peak RSS [MB] | trajectory RMSE [m] |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    print("| %d | %.1f | %.0fx | %d | %d | %.1f | %.0f | %.3f |" % (r["hour"], r["wall_s"], r["rtf"],
          r["nodes"], r["edges"], r["file_mb"], r["peak_rss_mb"], r["rmse_m"]))
wall = sum(r["wall_s"] for r in rows)
print()
print("%d h of data mapped in %.1f s of wall time (%.0fx real time); simulation took %.1f s; "
      "nodes after hour 1: %d, after hour %d: %d; peak RSS %.0f MB" % (hours, wall,
      hours * 3600.0 / wall, sim_s, rows[0]["nodes"], hours, rows[-1]["nodes"],
      max(r["peak_rss_mb"] for r in rows)))
json.dump({"hours": rows, "wall_s": wall, "simulation_s": sim_s},
          open(os.path.join(os.path.dirname(out), "bench_long.json"), "w"), indent=1)
PY
