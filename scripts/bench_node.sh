#!/usr/bin/env bash
# Benchmark of mapper_node on intel.bag: for each play rate (rosbag play --clock -r R) a fresh
# roscore and node map the whole bag; the table gives the scans the mapper got out of those in the
# bag, the scans dropped, and the node's CPU time and peak RSS. The highest rate that drops nothing
# is printed at the end. With --rt1 S the node also maps the first S seconds at -r 1 (CPU load and
# RSS at real time). Writes output/bench_node.json. Figures are measured, never asserted.
# Usage: scripts/bench_node.sh [--no-build] [--rt1 SECONDS] [RATE ...]   (default rates: 10 25 50 100)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
BAG="$DATA/intel/intel.bag"
OUT="$ROOT/output/bench_node"

BUILD=1
RT1_S=0
RATES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) BUILD=0 ;;
    --rt1) RT1_S="$2"; shift ;;
    *) RATES+=("$1") ;;
  esac
  shift
done
[ ${#RATES[@]} -gt 0 ] || RATES=(10 25 50 100)
if [ ! -f "$BAG" ]; then echo "bench_node.sh: no bag at $BAG" >&2; exit 1; fi
[ $BUILD -eq 0 ] || bench_build
set +u
# shellcheck disable=SC1091
source "$ROOT/build_ws/devel/setup.bash"
set -u
rm -rf "$OUT"
mkdir -p "$OUT"
export ROS_HOME="$OUT/ros_home"
export ROS_MASTER_URI="http://localhost:11391"
BAG_SCANS=$(rosbag info -y -k topics "$BAG" | /usr/bin/python3 -c \
  'import sys, yaml; print(next(t["messages"] for t in yaml.safe_load(sys.stdin) if t["topic"] == "/scan"))')

# One run: RATE, extra rosbag play arguments, result file. Prints nothing; writes JSON.
run_once() {
  local rate="$1" extra="$2" result="$3"
  roscore -p 11391 > "$OUT/roscore.log" 2>&1 &
  local core=$!
  for _ in $(seq 50); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
  rosparam set /use_sim_time true
  rosparam load "$ROOT/config/mapping.yaml" /mapper_node
  rosparam load "$ROOT/config/presets/freiburg.yaml" /mapper_node
  rosparam set /mapper_node/map_folder "$OUT/maps"
  "$ROOT/build_ws/devel/lib/longterm_mapper2d/mapper_node" __name:=mapper_node \
    > "$OUT/node_r$rate.log" 2>&1 &
  local node=$!
  sleep 2
  if ! kill -0 "$node" 2> /dev/null; then
    echo "bench_node.sh: mapper_node did not start:" >&2
    tail -5 "$OUT/node_r$rate.log" >&2
    kill -INT "$core"; wait "$core" || true
    exit 1
  fi
  local start end
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  rosbag play --clock -q --delay=2 -r "$rate" $extra "$BAG" > /dev/null 2>&1
  end=$(date +%s.%N)
  # The worker drains its queue; then the last status is read.
  local last=-1 now
  for _ in $(seq 120); do
    now=$(timeout 10 rostopic echo -n 1 /mapper_node/status/scans_received 2>/dev/null | head -1 || true)
    [ "$now" = "$last" ] && break
    last="$now"; sleep 3
  done
  timeout 20 rostopic echo -n 1 /mapper_node/status > "$OUT/status_r$rate.txt" 2>/dev/null || true
  local ticks rss_kb
  ticks=$(awk '{print $14 + $15}' "/proc/$node/stat")
  rss_kb=$(awk '/VmHWM/ {print $2}' "/proc/$node/status")
  kill -INT "$node"; wait "$node" || true
  kill -INT "$core"; wait "$core" || true
  /usr/bin/python3 - "$OUT/status_r$rate.txt" "$result" "$rate" "$start" "$end" "$ticks" \
    "$(getconf CLK_TCK)" "$rss_kb" "$BAG_SCANS" "$extra" <<'PY'
import json, sys, yaml
status_file, result, rate, start, end, ticks, hz, rss_kb, bag_scans, extra = sys.argv[1:]
docs = [d for d in yaml.safe_load_all(open(status_file)) if isinstance(d, dict)]
s = docs[0] if docs else {}
wall = float(end) - float(start)
cpu = int(ticks) / float(hz)
json.dump({"rate": float(rate), "play_args": extra, "play_wall_s": wall, "bag_scans": int(bag_scans),
           "scans_received": s.get("scans_received", 0), "scans_dropped": s.get("scans_dropped_no_tf", 0),
           "nodes": s.get("nodes", 0), "closures": s.get("loop_closures_accepted", 0),
           "node_cpu_s": cpu, "node_cpu_percent": 100.0 * cpu / wall if wall > 0 else 0.0,
           "node_peak_rss_mb": int(rss_kb) / 1024.0}, open(result, "w"))
PY
}

RESULTS=()
for rate in "${RATES[@]}"; do
  run_once "$rate" "" "$OUT/r$rate.json"
  RESULTS+=("$OUT/r$rate.json")
done
if [ "$RT1_S" != "0" ]; then
  run_once 1 "-u $RT1_S" "$OUT/r1.json"
  RESULTS+=("$OUT/r1.json")
fi

/usr/bin/python3 - "$ROOT/output/bench_node.json" "${RESULTS[@]}" <<'PY'
import json, sys
rows = [json.load(open(f)) for f in sys.argv[2:]]
print("| play rate | bag part | wall [s] | scans in bag | mapped | dropped | nodes | closures | node CPU [s] | CPU [%] | peak RSS [MB] |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    part = "first %s s" % r["play_args"].split()[1] if r["play_args"] else "whole"
    print("| %g | %s | %.0f | %d | %d | %d | %d | %d | %.1f | %.0f | %.0f |" % (
        r["rate"], part, r["play_wall_s"], r["bag_scans"], r["scans_received"], r["scans_dropped"],
        r["nodes"], r["closures"], r["node_cpu_s"], r["node_cpu_percent"], r["node_peak_rss_mb"]))
whole = [r for r in rows if not r["play_args"]]
# The bag's last scan has no odometry after it, so it waits for ever: at most one scan unmapped.
clean = [r["rate"] for r in whole if r["scans_received"] >= r["bag_scans"] - 1 and r["scans_dropped"] == 0]
print("\nhighest play rate without a dropped scan: %s" % (("-r %g" % max(clean)) if clean else "none of those tried"))
json.dump(rows, open(sys.argv[1], "w"), indent=2)
print("bench_node.sh: wrote %s" % sys.argv[1])
PY
