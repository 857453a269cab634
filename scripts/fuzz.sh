#!/usr/bin/env bash
# Builds the libFuzzer targets of the file parsers (test/fuzz/*_fuzzer.cpp: carmen, g2o, relations,
# ltmap) with ASan + UBSan straight from the core sources, seeds a corpus per target from
# ../shared/data (and synthetic session maps), runs each target and prints one line per target:
# name, runs executed, result. Exits non-zero if a target fails to build, crashes, times out or
# runs out of memory; the input that did it is kept under build_ws/fuzz/artifacts/<name>/.
# Everything lives under build_ws/fuzz/ (corpora grow from run to run); nothing else is touched.
# Options: --seconds N (per target, default 60), --target NAME (repeatable; default all),
#          --jobs N (targets built and fuzzed at the same time, default 1).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SCRIPT="$ROOT/scripts/fuzz.sh"
export PATH="/usr/bin:$PATH"

SECONDS_PER_TARGET=60
JOBS=1
TARGETS=()
ALL_TARGETS=(carmen g2o relations ltmap)
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) SECONDS_PER_TARGET="${2:?--seconds needs a value}"; shift ;;
    --target) TARGETS+=("${2:?--target needs a name}"); shift ;;
    --jobs) JOBS="${2:?--jobs needs a value}"; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
  shift
done
[[ "$SECONDS_PER_TARGET" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: bad --seconds" >&2; exit 2; }
[[ "$JOBS" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: bad --jobs" >&2; exit 2; }
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=("${ALL_TARGETS[@]}")
for t in "${TARGETS[@]}"; do
  case " ${ALL_TARGETS[*]} " in
    *" $t "*) ;;
    *) echo "fuzz.sh: unknown target '$t' (known: ${ALL_TARGETS[*]})" >&2; exit 2 ;;
  esac
done

CXX=clang++
FLAGS=(-std=c++17 -O1 -g "-fsanitize=fuzzer,address,undefined" -fno-sanitize-recover=undefined
       -I"$ROOT/include" -isystem /usr/include/eigen3)
OUT="$ROOT/build_ws/fuzz"
DATA="$(cd "$ROOT/.." && pwd)/shared/data"
mkdir -p "$OUT/obj" "$OUT/logs"

# The core sources each parser links against (no Ceres, no ROS).
sources_of() {
  case "$1" in
    carmen) echo io/carmen_reader io/atomic_file sensor/odometry_buffer geometry/pose2 ;;
    g2o) echo io/g2o_io io/atomic_file graph/pose_graph geometry/pose2 ;;
    relations) echo io/relations_reader io/number_table geometry/pose2 ;;
    ltmap) echo map/session_map_file io/binary_io io/atomic_file geometry/pose2 ;;
  esac
}
max_len_of() {
  case "$1" in
    carmen) echo 65536 ;;  # a few dozen FLASER lines
    g2o) echo 65536 ;;
    relations) echo 16384 ;;
    ltmap) echo 65536 ;;
  esac
}

# Tokens the mutator splices into text inputs (one per line, as libFuzzer -dict= reads them).
dictionary_of() {
  local numbers='"nan"\n"-nan"\n"inf"\n"-inf"\n"1e308"\n"-1e308"\n"4.9e-324"\n"0x1p+1023"\n"-0"\n"#"\n"\\x0a"'
  case "$1" in
    carmen) printf '%b\n' "$numbers" '"FLASER"\n"RLASER"\n"ROBOTLASER1"\n"ODOM"\n"180"\n"361"\n"100000"' ;;
    g2o) printf '%b\n' "$numbers" '"VERTEX_SE2"\n"EDGE_SE2"\n"VERTEX2"\n"EDGE2"\n"FIX"' \
           '"9223372036854775807"\n"-9223372036854775808"' ;;
    relations) printf '%b\n' "$numbers" '"3.14159265358979"\n"-3.14159265358979"' ;;
    ltmap) printf '%s\n' '"LTMAP2D\x0a"' '"\x01\x00\x00\x00"' '"\x02\x00\x00\x00"' ;;
  esac
}

# True when $1 is missing or older than any of the remaining files or any header.
stale() {
  local target="$1"
  shift
  [ -e "$target" ] || return 0
  local f
  for f in "$@" "$SCRIPT"; do [ "$f" -nt "$target" ] && return 0; done
  [ -n "$(find "$ROOT/include" -name '*.h' -newer "$target" -print -quit)" ]
}

# Compiles the core objects of a target (shared between targets) and links the fuzzer.
build_target() {
  local name="$1" objects=() src obj
  for src in $(sources_of "$name"); do
    obj="$OUT/obj/${src//\//_}.o"
    if stale "$obj" "$ROOT/src/core/$src.cpp"; then
      "$CXX" "${FLAGS[@]}" -c "$ROOT/src/core/$src.cpp" -o "$obj.$BASHPID" || return 1
      mv "$obj.$BASHPID" "$obj"
    fi
    objects+=("$obj")
  done
  local fuzzer_src="$ROOT/test/fuzz/${name}_fuzzer.cpp" bin="$OUT/${name}_fuzzer"
  if stale "$bin" "$fuzzer_src" "${objects[@]}"; then
    "$CXX" "${FLAGS[@]}" "$fuzzer_src" "${objects[@]}" -o "$bin.$BASHPID" || return 1
    mv "$bin.$BASHPID" "$bin"
  fi
}

# Copies the first $2 lines of $1 into corpus $3 as seed-<file name>, once.
seed_head() {
  local file="$1" lines="$2" corpus="$3" seed
  seed="$corpus/seed-$(basename "$file")"
  if [ -f "$file" ] && [ ! -e "$seed" ]; then head -n "$lines" "$file" > "$seed" || true; fi
}

seed_carmen() {
  local c="$1" f
  for f in "$DATA"/intel/intel.reconstructed.clf "$DATA"/aces/aces.reconstructed.clf \
           "$DATA"/fr079/fr079.reconstructed.clf "$DATA"/mit-killian/mit-killian.synthetic_time.clf \
           "$DATA"/radish-gfs-corrected/{intel,orebro,csail,infinite-corridor,seattle}-corrected.log; do
    seed_head "$f" 200 "$c"
  done
  # No shared log has ROBOTLASER1 or RLASER records: a hand-written one.
  [ -e "$c/seed-robotlaser" ] || cat > "$c/seed-robotlaser" <<'EOF'
# synthetic
ODOM 0.0 0.0 0.0 0 0 0 10.0 host 10.0
ROBOTLASER1 0 -1.5708 3.1416 0.0175 30.0 0.01 0 5 1.0 2.0 30.0 2.5 3.0 0 0.2 0.0 0.0 0.0 0.0 0.0 0 0 0.5 0.5 0.0 10.1 host 10.1
ODOM 1.0 0.0 0.1 0 0 0 11.0 host 11.0
RLASER 4 1.0 1.5 2.0 2.5 0.0 0.0 0.0 0.0 0.0 0.0 10.5 host 10.5
EOF
}

seed_g2o() {
  local c="$1" f
  for f in "$DATA"/posegraph-2d/se-sync/{CSAIL,MIT,intel,manhattan}.g2o \
           "$DATA"/posegraph-2d/vertigo/ring.g2o "$DATA"/posegraph-2d/hog-man/w10000.graph; do
    [ -f "$f" ] || continue
    local seed
    seed="$c/seed-$(basename "$f")"
    # Most files list every vertex first: take the first vertices and the first edges.
    [ -e "$seed" ] || { head -n 150 "$f"; grep -m 150 '^EDGE' "$f" || true; } > "$seed"
  done
}

seed_relations() {
  local c="$1" f
  for f in "$DATA"/*/*.relations; do seed_head "$f" 100 "$c"; done
}

# Session maps: serialised synthetic maps (generator built with the same core sources), and the
# map of a short real run when the offline mapper has been built.
seed_ltmap() {
  local c="$1" gen="$OUT/ltmap_seed_generator"
  if stale "$gen" "$ROOT/src/core/map/session_map_file.cpp"; then
    cat > "$OUT/ltmap_seed_generator.cpp" <<'EOF'
#include <cmath>
#include <fstream>
#include <limits>

#include "longterm_mapper2d/core/io/binary_io.h"
#include "longterm_mapper2d/core/map/session_map_file.h"

namespace ltm = longterm_mapper2d;

ltm::SessionMap Map(int nodes, int points, int beams) {
  ltm::SessionMap map;
  map.sessions = nodes > 1 ? 2 : 1;
  map.gauge = 1;
  map.origin = ltm::Pose2(0.5, -0.5, 0.2);
  for (int id = 1; id <= nodes; ++id) {
    ltm::LocalMapNode node;
    node.id = id;
    node.session_id = id > 2;
    node.stamp_s = 100.0 + id;
    node.map_T_node = ltm::Pose2(id, 0.1 * id, 0.3 * id);
    for (int k = 0; k < points; ++k) {
      ltm::RichPoint p;
      p.point_m = Eigen::Vector2d(0.1 * k, -0.2 * k);
      p.normal = k % 2 ? Eigen::Vector2d(0.6, 0.8) : Eigen::Vector2d::Zero();
      p.weight = 1.0 / (k + 1);
      node.cloud.push_back(p);
    }
    ltm::Waypoint w;
    w.node_T_base = ltm::Pose2(-0.1, 0.0, -0.05);
    w.base_T_laser = ltm::Pose2(0.2, 0.0, M_PI);
    w.scan.stamp_s = 99.9 + id;
    w.scan.frame_id = "laser";
    w.scan.angle_min_rad = -M_PI / 2;
    w.scan.angle_increment_rad = M_PI / 180;
    w.scan.range_min_m = 0.05;
    w.scan.range_max_m = 30.0;
    for (int b = 0; b < beams; ++b) {
      w.scan.ranges.push_back(b % 7 ? 1.0f + 0.01f * b : std::numeric_limits<float>::infinity());
    }
    node.waypoints.push_back(w);
    map.nodes.emplace(id, node);
  }
  for (int id = 1; id < nodes; ++id) {
    ltm::GraphEdge e;
    e.from = id;
    e.to = id + 1;
    e.kind = static_cast<ltm::EdgeKind>(id % 3);
    e.session_id = id > 2;
    e.stamp_s = 100.5 + id;
    e.measurement = ltm::Pose2(1.0, 0.1, 0.3);
    e.information << 100, 1, 2, 1, 90, 3, 2, 3, 400;
    map.edges.push_back(e);
  }
  return map;
}

void Write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  Write(dir + "/seed-empty.ltmap", ltm::SerializeSessionMap(ltm::SessionMap()));
  Write(dir + "/seed-one-node.ltmap", ltm::SerializeSessionMap(Map(1, 3, 4)));
  Write(dir + "/seed-three-nodes.ltmap", ltm::SerializeSessionMap(Map(3, 5, 10)));
  Write(dir + "/seed-six-nodes.ltmap", ltm::SerializeSessionMap(Map(6, 20, 181)));
  ltm::SessionMap no_edges = Map(3, 1, 2);
  no_edges.edges.clear();
  Write(dir + "/seed-no-edges.ltmap", ltm::SerializeSessionMap(no_edges));
  // Version 1: no origin (24 bytes after sessions and gauge).
  const std::string v2 = ltm::SerializeSessionMap(Map(2, 2, 3));
  const std::string body = v2.substr(24, 12) + v2.substr(24 + 12 + 24);
  ltm::BinaryWriter v1;
  v1.WriteBytes("LTMAP2D\n");
  v1.Write<std::uint32_t>(1);
  v1.Write<std::uint64_t>(body.size());
  v1.Write<std::uint32_t>(ltm::Crc32(body.data(), body.size()));
  v1.WriteBytes(body);
  Write(dir + "/seed-version1.ltmap", v1.bytes());
  return 0;
}
EOF
    "$CXX" -std=c++17 -O1 -I"$ROOT/include" -isystem /usr/include/eigen3 \
      "$OUT/ltmap_seed_generator.cpp" "$ROOT"/src/core/map/session_map_file.cpp \
      "$ROOT"/src/core/io/{binary_io,atomic_file}.cpp "$ROOT"/src/core/geometry/pose2.cpp \
      -o "$gen.$BASHPID" || return 1
    mv "$gen.$BASHPID" "$gen"
  fi
  [ -e "$c/seed-no-edges.ltmap" ] || "$gen" "$c"
  local mapper="$ROOT/build_ws/devel/lib/longterm_mapper2d/offline_mapper"
  if [ -x "$mapper" ] && [ -f "$DATA/intel/intel.bag" ] && [ ! -e "$OUT/logs/offline_mapper.log" ]; then
    # Tried once (its log marks it), best effort: a failure only means one seed less.
    timeout 300 "$mapper" --bag "$DATA/intel/intel.bag" --end 20 \
      --save-map "$OUT/intel-20s.ltmap" > "$OUT/logs/offline_mapper.log" 2>&1 || true
    # A map larger than max_len would only be cut short: keep it if it fits.
    if [ -e "$OUT/intel-20s.ltmap" ] &&
       [ "$(stat -c %s "$OUT/intel-20s.ltmap")" -le "$(max_len_of ltmap)" ]; then
      cp "$OUT/intel-20s.ltmap" "$c/seed-intel-20s.ltmap"
    fi
  fi
}

# Builds, seeds and fuzzes one target; writes "runs<TAB>result" to $OUT/logs/<name>.result.
run_target() {
  local name="$1" corpus="$OUT/corpus_$1" artifacts="$OUT/artifacts/$1"
  local log="$OUT/logs/$1.log" result="$OUT/logs/$1.result"
  rm -f "$result"
  if ! build_target "$name" > "$OUT/logs/$name.build.log" 2>&1; then
    printf -- '-\tBUILD FAILED (see %s)\n' "$OUT/logs/$name.build.log" > "$result"
    return 0
  fi
  mkdir -p "$corpus" "$artifacts"
  case "$name" in
    carmen) seed_carmen "$corpus" ;;
    g2o) seed_g2o "$corpus" ;;
    relations) seed_relations "$corpus" ;;
    ltmap) seed_ltmap "$corpus" ;;
  esac >> "$OUT/logs/$name.build.log" 2>&1 || true
  dictionary_of "$name" > "$OUT/$name.dict"
  local status=0
  ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=1" UBSAN_OPTIONS="print_stacktrace=1" \
    "$OUT/${name}_fuzzer" "$corpus" -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=2048 \
    -max_len="$(max_len_of "$name")" -timeout=10 -print_final_stats=1 -dict="$OUT/$name.dict" \
    -artifact_prefix="$artifacts/" > "$log" 2>&1 || status=$?
  local runs
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)"
  [ -n "$runs" ] || runs="$(sed -n 's/^Done \([0-9]*\) runs.*/\1/p' "$log" | tail -n 1)"
  [ -n "$runs" ] || runs="?"
  local artifact
  artifact="$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)"
  if [ $status -eq 0 ] && [ -z "$artifact" ]; then
    printf '%s\tok\n' "$runs" > "$result"
  else
    local why
    why="$(grep -m 1 -oE 'SUMMARY: [A-Za-z]+Sanitizer: [^ ]+( [^ ]+)?|ERROR: libFuzzer: [a-z -]+|runtime error: .*' \
      "$log" || true)"
    [ -n "$why" ] || why="exit status $status"
    printf '%s\tFAILED: %s; input: %s; log: %s\n' "$runs" "$why" "${artifact:-none}" "$log" \
      > "$result"
  fi
}

running=0
for t in "${TARGETS[@]}"; do
  run_target "$t" &
  running=$((running + 1))
  if [ $running -ge "$JOBS" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true

failed=0
printf '%-10s %12s  %s\n' target runs result
for t in "${TARGETS[@]}"; do
  if [ -f "$OUT/logs/$t.result" ]; then
    IFS=$'\t' read -r runs result < "$OUT/logs/$t.result"
  else
    runs="-"
    result="FAILED: no result (see $OUT/logs/$t.log)"
  fi
  [ "$result" = ok ] || failed=1
  printf '%-10s %12s  %s\n' "$t" "$runs" "$result"
done
exit $failed
