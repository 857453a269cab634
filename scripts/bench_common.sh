# Sourced by the bench scripts: where the project, the data and the executables are, and the
# install-and-build step each runs unless given --no-build.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:$PATH"  # the system python3 (ROS modules), not a user one first in PATH
DATA="$(cd "$ROOT/.." && pwd)/shared/data"
BIN="$ROOT/build_ws/devel/lib/longterm_mapper2d"

# Installs the dependencies and builds; on a failed build, the end of its log and exit 1.
bench_build() {
  bash "$ROOT/scripts/install_deps.sh" > /dev/null
  mkdir -p "$ROOT/output"
  bash "$ROOT/scripts/build.sh" > "$ROOT/output/build.log" 2>&1 || {
    tail -30 "$ROOT/output/build.log"
    exit 1
  }
}

# Exits with a message naming the calling script when ../shared/data is missing.
bench_require_data() {
  if [ ! -d "$DATA" ]; then
    echo "$(basename "$0"): no data folder at $DATA" >&2
    exit 1
  fi
}
