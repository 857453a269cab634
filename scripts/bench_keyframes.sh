#!/usr/bin/env bash
# Benchmark on other buildings and lasers: the thirteen GMapping-corrected keyframe logs of
# ../shared/data/radish-gfs-corrected, given a drifting odometry by scripts/keyframe_logs.py
# (see there: 0.5-1 m between scans, the reference is GMapping's own map). Maps each with the
# default configuration (or --config FILE) and with odometry alone, and prints per log the beams,
# scans, tracker failures, accepted closures, nodes and the mean (largest) relation error of
# both; writes output/bench_keyframes.json. Figures are measured, never asserted.
# Usage: scripts/bench_keyframes.sh [--no-build] [--config FILE.yaml] [NAME ...]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench_keyframes"

BUILD=1
CONFIG="$ROOT/config/mapping.yaml"
NAMES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) BUILD=0 ;;
    --config) CONFIG="$(realpath "${2:?--config needs a file}")"; shift ;;
    -*) echo "bench_keyframes.sh: unknown option '$1'" >&2; exit 2 ;;
    *) NAMES+=("$1") ;;
  esac
  shift
done
if [ ! -d "$DATA/radish-gfs-corrected" ]; then
  echo "bench_keyframes.sh: no $DATA/radish-gfs-corrected" >&2; exit 1
fi
[ $BUILD -eq 0 ] || bench_build
mkdir -p "$OUT"
/usr/bin/python3 "$ROOT/scripts/keyframe_logs.py" "$DATA" "$OUT" "${NAMES[@]}" > /dev/null
# The logs keyframe_logs.py wrote, by their relations (each run's own .log files are not logs).
[ ${#NAMES[@]} -gt 0 ] || mapfile -t NAMES < <(cd "$OUT" && ls *.relations | sed 's/\.relations$//')

for n in "${NAMES[@]}"; do
  for run in mapper odometry; do
    cfg="$CONFIG"; [ $run = odometry ] && cfg="$ROOT/config/odometry_only.yaml"
    "$BIN/offline_mapper" --carmen "$OUT/$n.log" --config "$cfg" \
      --trajectory "$OUT/$n.$run.trajectory.txt" --stats "$OUT/$n.$run.stats.json" \
      2> "$OUT/$n.$run.log" > /dev/null
    "$BIN/evaluate_relations" --json --trajectory "$OUT/$n.$run.trajectory.txt" \
      --relations "$OUT/$n.relations" > "$OUT/$n.$run.relations.json"
  done
done

/usr/bin/python3 - "$OUT" "${NAMES[@]}" <<'PY'
import json, os, sys
out, names = sys.argv[1], sys.argv[2:]
rows = []
print("| log | beams | scans | tracker failures | closures | nodes | odometry [m] | mapper [m] | mapper rot [deg] |")
print("|---|---|---|---|---|---|---|---|---|")
for n in names:
    beams = int(open(os.path.join(out, n + ".log")).readline().split()[1])
    s = json.load(open(os.path.join(out, n + ".mapper.stats.json")))
    c = s["counters"]
    r = json.load(open(os.path.join(out, n + ".mapper.relations.json")))
    o = json.load(open(os.path.join(out, n + ".odometry.relations.json")))
    row = {"log": n, "beams": beams, "scans": s["scans_read"],
           "tracker_failures": c.get("tracker_failures", 0),
           "closures": c.get("loop_closures_accepted", 0), "nodes": c.get("nodes", 0),
           "odometry_err_m": o["trans_abs_mean_m"], "odometry_err_max_m": o["trans_max_m"],
           "trans_err_m": r["trans_abs_mean_m"], "trans_err_max_m": r["trans_max_m"],
           "rot_err_deg": r["rot_abs_mean_deg"], "wall_time_s": s["wall_time_s"]}
    rows.append(row)
    print("| %s | %d | %d | %d | %d | %d | %.3f (max %.1f) | %.3f (max %.2f) | %.2f |" % (
        n, beams, row["scans"], row["tracker_failures"], row["closures"], row["nodes"],
        row["odometry_err_m"], row["odometry_err_max_m"], row["trans_err_m"],
        row["trans_err_max_m"], row["rot_err_deg"]))
json.dump(rows, open(os.path.join(os.path.dirname(out), "bench_keyframes.json"), "w"), indent=2)
print("\nrelation errors against GMapping's corrected poses (not ground truth)")
print("bench_keyframes.sh: wrote %s" % os.path.join(os.path.dirname(out), "bench_keyframes.json"))
PY
