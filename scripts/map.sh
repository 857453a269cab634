#!/usr/bin/env bash
# Installs what is missing, builds, and maps.
#   scripts/map.sh                      built-in demo: three simulated sessions of a care-home floor
#                                       (people walking, furniture moved between sessions)
#   scripts/map.sh --world FILE.yaml [--duration S]
#                                       the demo on another world, e.g. config/worlds/small_room.yaml
#                                       with --duration 240 (a fast one)
#   scripts/map.sh --bag FILE [--bag FILE ...] [offline_mapper options]
#   scripts/map.sh --carmen FILE        [offline_mapper options]
# Results go to output/ (map .pgm/.yaml/.png, trajectory, stats).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:$PATH"
OUT="$ROOT/output"

bash "$ROOT/scripts/install_deps.sh"
bash "$ROOT/scripts/build.sh" > "$ROOT/build_ws_build.log" 2>&1 || {
  tail -n 40 "$ROOT/build_ws_build.log"; echo "map.sh: build failed (log: build_ws_build.log)"; exit 1; }
BIN="$ROOT/build_ws/devel/lib/longterm_mapper2d"
set +u
# shellcheck disable=SC1091
source "$ROOT/build_ws/devel/setup.bash"
set -u

mkdir -p "$OUT"
if [ "${1:-}" = "--world" ]; then
  world="${2:?map.sh: --world needs a file}"
  duration=430
  if [ "${3:-}" = "--duration" ]; then duration="${4:?map.sh: --duration needs seconds}"; fi
  exec bash "$ROOT/scripts/demo.sh" "$OUT" "$world" 3 "$duration"
fi
if [ $# -gt 0 ]; then
  name="mapped"
  "$BIN/offline_mapper" "$@" --output-dir "$OUT/$name"
  echo
  echo "map.sh: done. Look at $OUT/$name/map.png (and map.pgm/.yaml, trajectory.txt, stats.json)."
  exit 0
fi

exec bash "$ROOT/scripts/demo.sh" "$OUT"
