#!/usr/bin/env bash
# Long-term benchmark: maps the whole intel bag N times in a row (default 10), each session
# loading the previous session's map and starting at the docking station (the map's origin).
# Prints per session the wall time, optimisation time per node, nodes, edges, map file size,
# peak RSS and the relation error, as a table and as output/bench_sessions.json. Measured, never
# asserted. Usage: scripts/bench_sessions.sh [--no-build] [--no-maintenance] [N]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench_sessions"
BUILD=1
SESSIONS=10
EXTRA=()
for arg in "$@"; do
  case "$arg" in
    --no-build) BUILD=0 ;;
    --no-maintenance) EXTRA+=(--no-maintenance) ;;
    [0-9]*) SESSIONS="$arg" ;;
    *) echo "bench_sessions.sh: unknown option '$arg'" >&2; exit 2 ;;
  esac
done
if [ ! -f "$DATA/intel/intel.bag" ]; then echo "bench_sessions.sh: no intel bag in $DATA" >&2; exit 1; fi
[ $BUILD -eq 0 ] || bench_build
rm -rf "$OUT"
mkdir -p "$OUT"
previous=()
for s in $(seq 1 "$SESSIONS"); do
  "$BIN/offline_mapper" --bag "$DATA/intel/intel.bag" "${previous[@]}" "${EXTRA[@]}" \
    --save-map "$OUT/session$s.ltmap" --trajectory "$OUT/session$s.trajectory.txt" \
    --stats "$OUT/session$s.stats.json" 2> "$OUT/session$s.log"
  "$BIN/evaluate_relations" --json --trajectory "$OUT/session$s.trajectory.txt" \
    --relations "$DATA/intel/intel.relations" > "$OUT/session$s.relations.json"
  previous=(--load-map "$OUT/session$s.ltmap")
  echo "bench_sessions.sh: session $s done" >&2
done

/usr/bin/python3 - "$OUT" "$SESSIONS" <<'PY'
import json, os, sys
out, n = sys.argv[1], int(sys.argv[2])
rows = []
for s in range(1, n + 1):
    st = json.load(open(os.path.join(out, "session%d.stats.json" % s)))
    rel = json.load(open(os.path.join(out, "session%d.relations.json" % s)))
    g = st["graph"]
    nodes = g["nodes"]
    opt = st["stage_time_s"].get("optimization", 0.0)
    rows.append({"session": s, "wall_s": st["wall_time_s"], "optimization_s": opt,
                 "optimization_ms_per_node": 1000.0 * opt / max(nodes, 1), "nodes": nodes,
                 "edges": g["edges_odometry"] + g["edges_loop_closure"] + g["edges_condensed"],
                 "edges_condensed": g["edges_condensed"], "merges": st["counters"].get("merges", 0),
                 "map_file_mb": st.get("map_file_bytes", 0) / 1e6, "peak_rss_mb": st["peak_rss_mb"],
                 "trans_err_m": rel["trans_abs_mean_m"], "rot_err_deg": rel["rot_abs_mean_deg"]})
hdr = ("| session | wall [s] | optimisation [ms/node] | nodes | edges (condensed) | merges | "
       "map file [MB] | peak RSS [MB] | rel. error [m] / [deg] |")
print(hdr)
print("|" + "---|" * (hdr.count("|") - 1))
for r in rows:
    print("| %d | %.1f | %.2f | %d | %d (%d) | %d | %.1f | %.0f | %.3f / %.2f |" % (
        r["session"], r["wall_s"], r["optimization_ms_per_node"], r["nodes"], r["edges"],
        r["edges_condensed"], r["merges"], r["map_file_mb"], r["peak_rss_mb"], r["trans_err_m"],
        r["rot_err_deg"]))
if len(rows) >= 2:
    print("\nsession %d / session 1: nodes %.2fx, map file %.2fx; wall time session %d / session 2: %.2fx" % (
        n, rows[-1]["nodes"] / rows[0]["nodes"], rows[-1]["map_file_mb"] / max(rows[0]["map_file_mb"], 1e-9),
        n, rows[-1]["wall_s"] / rows[1]["wall_s"]))
json.dump(rows, open(os.path.join(os.path.dirname(out), "bench_sessions.json"), "w"), indent=2)
PY
