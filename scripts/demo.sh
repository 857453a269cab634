#!/usr/bin/env bash
# The built-in demo (scripts/map.sh with no arguments): simulates sessions of a world with people
# and furniture that moves between sessions, maps them one after another (each session loads the
# map saved by the previous one), scores every map against that session's simulated ground truth
# and writes OUT/report.md. Usage: demo.sh OUT_DIR [WORLD.yaml] [SESSIONS] [DURATION_S]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:?usage: demo.sh OUT_DIR [WORLD.yaml] [SESSIONS] [DURATION_S]}"
WORLD="${2:-$ROOT/config/worlds/small_room.yaml}"
SESSIONS="${3:-3}"
DURATION="${4:-240}"
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
  echo "session, and compared with that session's true world."
  echo
  echo "| session | scans | processed | wall time [s] | nodes | loop closures | map file [kB] | precision | recall | phantom cells |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
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
  /usr/bin/python3 - "$dir" "$k" >> "$REPORT" <<'PY'
import json, sys
d, k = sys.argv[1], sys.argv[2]
s = json.load(open(d + "/stats.json"))
q = json.load(open(d + "/map_quality.json"))
import os
g = s["graph"]
print("| %s | %d | %d | %.2f | %d | %d | %.0f | %.3f | %.3f | %d |" % (k, s["scans_read"],
      s["scans_processed"], s["wall_time_s"], g["nodes"], g["edges_loop_closure"],
      os.path.getsize(d + "/map.ltmap") / 1024.0, q["precision"], q["recall"], q["phantom_cells"]))
PY
done

{
  echo
  echo "Per session: session_k/map.png (the map), map.pgm/.yaml (map_server format), map.ltmap"
  echo "(the session map the next session loads), trajectory.txt, stats.json, difference.png"
  echo "(green correct, red phantom, blue missed). Local maps that a session revisits merge into its"
  echo "newest node and the older node is removed, so the graph stays the size of the room."
} >> "$REPORT"

echo
cat "$REPORT"
echo
echo "demo: done. Look at $OUT/report.md and the maps in $OUT/session_*/map.png"
