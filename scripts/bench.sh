#!/usr/bin/env bash
# Benchmark: offline_mapper on the Freiburg bags in ../shared/data. Prints per dataset the scans,
# processed scans, nodes, wall time, real-time factor, time per stage (the trajectory's final
# refinement included) and peak RSS, and the relation error; writes the same to
# output/bench.json. Then the multi-session run (N whole
# intel sessions, each on the previous map: scripts/bench_sessions.sh, output/bench_sessions.json)
# and, if asked, the long run (H hours of the simulated care home: scripts/bench_long.sh,
# output/bench_long.json). Figures are measured, never asserted.
# Usage: scripts/bench.sh [--no-build] [--sessions N (default 10, 0: none)] [--long H]
#                         [DATASET ...]   (default: intel aces fr079; also mit-killian,
#                         whose stamps scripts/restore_killian_stamps.py restores first)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench"

BUILD=1
SESSIONS=10
HOURS=0
DATASETS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) BUILD=0 ;;
    --sessions) SESSIONS="${2:?--sessions needs a number}"; shift ;;
    --long) HOURS="${2:?--long needs a number of hours}"; shift ;;
    -*) echo "bench.sh: unknown option '$1'" >&2; exit 2 ;;
    *) DATASETS+=("$1") ;;
  esac
  shift
done
[ ${#DATASETS[@]} -gt 0 ] || DATASETS=(intel aces fr079)
bench_require_data
[ $BUILD -eq 0 ] || bench_build
mkdir -p "$OUT"

for d in "${DATASETS[@]}"; do
  if [ "$d" = mit-killian ]; then
    # Its only copy lost the scan stamps; restored from the relations (see the script).
    /usr/bin/python3 "$ROOT/scripts/restore_killian_stamps.py" "$DATA" "$OUT/$d.clf"
    INPUT=(--carmen "$OUT/$d.clf")
  else
    INPUT=(--bag "$DATA/$d/$d.bag")
  fi
  "$BIN/offline_mapper" "${INPUT[@]}" --trajectory "$OUT/$d.trajectory.txt" \
    --stats "$OUT/$d.stats.json" 2> "$OUT/$d.log"
  "$BIN/evaluate_relations" --json --trajectory "$OUT/$d.trajectory.txt" \
    --relations "$DATA/$d/$d.relations" > "$OUT/$d.relations.json"
done

/usr/bin/python3 - "$OUT" "${DATASETS[@]}" <<'PY'
import json, os, sys
out, names = sys.argv[1], sys.argv[2:]
rows = []
for d in names:
    s = json.load(open(os.path.join(out, d + ".stats.json")))
    r = json.load(open(os.path.join(out, d + ".relations.json")))
    st = s["stage_time_s"]
    rows.append({
        "dataset": d, "scans": s["scans_read"], "processed": s["scans_processed"],
        "nodes": s["counters"].get("nodes", 0), "tracker_failures": s["counters"].get("tracker_failures", 0),
        "data_s": s["data_duration_s"], "wall_s": s["wall_time_s"], "rtf": s["real_time_factor"],
        "reading_s": st.get("reading_odometry", 0.0) + st.get("reading", 0.0),
        "conversion_s": st.get("conversion", 0.0), "normals_s": st.get("normals", 0.0),
        "registration_s": st.get("registration", 0.0), "merging_s": st.get("merging", 0.0),
        "loop_closing_s": st.get("loop_closing", 0.0) - st.get("optimization", 0.0),
        "optimization_s": st.get("optimization", 0.0),
        "refinement_s": st.get("trajectory_refinement", 0.0),
        "closure_candidates": s["counters"].get("loop_closure_candidates", 0),
        "closures_accepted": s["counters"].get("loop_closures_accepted", 0),
        "peak_rss_mb": s["peak_rss_mb"], "trans_err_m": r["trans_abs_mean_m"],
        "rot_err_deg": r["rot_abs_mean_deg"]})
hdr = ("| dataset | scans | processed | nodes | data [s] | wall [s] | real-time factor | reading [s] | "
       "conversion [s] | normals [s] | registration [s] | merging [s] | loop closing [s] | "
       "optimisation [s] | refinement [s] | closures found / accepted | peak RSS [MB] | rel. error [m] / [deg] |")
print(hdr)
print("|" + "---|" * (hdr.count("|") - 1))
for x in rows:
    print("| %s | %d | %d | %d | %.0f | %.2f | %.0fx | %.2f | %.3f | %.3f | %.3f | %.3f | %.2f | %.3f | %.2f | %d / %d | %.0f | %.3f / %.2f |" % (
        x["dataset"], x["scans"], x["processed"], x["nodes"], x["data_s"], x["wall_s"], x["rtf"],
        x["reading_s"], x["conversion_s"], x["normals_s"], x["registration_s"], x["merging_s"],
        x["loop_closing_s"], x["optimization_s"], x["refinement_s"], x["closure_candidates"], x["closures_accepted"],
        x["peak_rss_mb"], x["trans_err_m"], x["rot_err_deg"]))
json.dump(rows, open(os.path.join(os.path.dirname(out), "bench.json"), "w"), indent=2)
print("\nbench.sh: wrote %s" % os.path.join(os.path.dirname(out), "bench.json"))
PY

if [ "$SESSIONS" -gt 0 ]; then
  echo
  bash "$ROOT/scripts/bench_sessions.sh" --no-build "$SESSIONS"
fi
if [ "$HOURS" -gt 0 ]; then
  echo
  bash "$ROOT/scripts/bench_long.sh" --no-build "$HOURS"
fi
