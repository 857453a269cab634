#!/usr/bin/env bash
# The built-in demo (scripts/map.sh with no arguments): simulates sessions of a world with people
# and furniture that moves between sessions, maps them one after another (each session loads the
# map saved by the previous one), scores every map against that session's simulated ground truth
# and writes OUT/report.md. Usage: demo.sh OUT_DIR [WORLD.yaml] [SESSIONS] [DURATION_S]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:?usage: demo.sh OUT_DIR [WORLD.yaml] [SESSIONS] [DURATION_S]}"
WORLD="${2:-$ROOT/config/worlds/care_home.yaml}"
SESSIONS="${3:-3}"
DURATION="${4:-430}"
BIN="$ROOT/build_ws/devel/lib/longterm_mapper2d"

mkdir -p "$OUT/sim"
echo "demo: simulating $SESSIONS sessions of $(basename "$WORLD" .yaml)"
"$BIN/simulate_world" --world "$WORLD" --out "$OUT/sim" --sessions "$SESSIONS" --seed 1 \
  --duration "$DURATION"

REPORT="$OUT/report.md"
{
  echo "# Demo report: $(basename "$WORLD" .yaml), $SESSIONS sessions"
  echo
  echo "Each session is mapped from its simulated bag on top of the map saved by the previous"
  echo "session, and compared with that session's true world: precision counts occupied map cells"
  echo "within one cell of a cell a true wall or object touches (a wall on a grid line touches the"
  echo "cells on both sides), \"on a true cell\" those on such a cell itself (no tolerance); recall"
  echo "counts observed true cells within one cell of an occupied map cell."
  echo
  echo "| session | scans | processed | wall time [s] | nodes | closures accepted | merges | map file [kB] | precision | on a true cell | recall | phantom cells | trajectory RMSE [m] |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} > "$REPORT"

for k in $(seq 1 "$SESSIONS"); do
  dir="$OUT/session_$k"
  load=()
  if [ "$k" -gt 1 ]; then load=(--load-map "$OUT/session_$((k - 1))/map.ltmap"); fi
  "$BIN/offline_mapper" --bag "$OUT/sim/session_$k.bag" "${load[@]}" --save-map "$dir.ltmap.tmp" \
    --output-dir "$dir" 2> "$dir.log" || { cat "$dir.log"; exit 1; }
  mv "$dir.ltmap.tmp" "$dir/map.ltmap"
  "$BIN/evaluate_map" --map "$dir/map.yaml" --truth "$OUT/sim/session_${k}_truth.yaml" --json \
    --diff "$dir/difference.png" > "$dir/map_quality.json"
  /usr/bin/python3 - "$dir" "$k" "$OUT/sim/session_${k}_truth_trajectory.txt" "$ROOT/scripts" \
    >> "$REPORT" <<'PY'
import json, os, sys
d, k, truth_path = sys.argv[1], sys.argv[2], sys.argv[3]
sys.dont_write_bytecode = True
sys.path.insert(0, sys.argv[4])
from trajectory_rmse import rmse
s = json.load(open(d + "/stats.json"))
q = json.load(open(d + "/map_quality.json"))
c = s["counters"]
print("| %s | %d | %d | %.2f | %d | %d | %d | %.0f | %.3f | %.3f | %.3f | %d | %.3f |" % (k,
      s["scans_read"], s["scans_processed"], s["wall_time_s"], s["graph"]["nodes"],
      c.get("loop_closures_accepted", 0), c.get("merges", 0),
      os.path.getsize(d + "/map.ltmap") / 1024.0, q["precision"], q["precision_on_truth"],
      q["recall"], q["phantom_cells"],
      rmse(d + "/trajectory.txt", truth_path)))
PY
done

# What changed between consecutive sessions: the later map compared with the earlier one.
{
  echo
  echo "Changes between consecutive maps (change_k.png: red appeared since session k-1, dark blue"
  echo "gone although session k looked there, light blue not seen again, green unchanged):"
  echo
  echo "| sessions | occupied cells appeared | occupied cells gone |"
  echo "|---|---|---|"
} >> "$REPORT"
for k in $(seq 2 "$SESSIONS"); do
  "$BIN/evaluate_map" --map "$OUT/session_$k/map.yaml" --truth "$OUT/session_$((k - 1))/map.yaml" \
    --json --diff "$OUT/change_$k.png" > "$OUT/session_$k/change.json"
  /usr/bin/python3 - "$OUT/session_$k/change.json" "$k" >> "$REPORT" <<'PY'
import json, sys
c, k = json.load(open(sys.argv[1])), int(sys.argv[2])
print("| %d -> %d | %d | %d |" % (k - 1, k, c["phantom_cells"], c["truth_observed"] - c["recalled"]))
PY
done

{
  echo
  echo "Per session: session_k/map.png (the map), map.pgm/.yaml (map_server format), map.ltmap"
  echo "(the session map the next session loads), trajectory.txt, stats.json, difference.png"
  echo "(green correct, red phantom, blue missed). Local maps that a session revisits merge into its"
  echo "newest node and the older node is removed, so the graph stays the size of the building."
} >> "$REPORT"

echo
cat "$REPORT"
echo
echo "demo: done. Look at $OUT/report.md, the maps in $OUT/session_*/map.png and the changes in $OUT/change_*.png"
