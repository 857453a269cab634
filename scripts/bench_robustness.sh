#!/usr/bin/env bash
# Robustness benchmark: the Freiburg logs mapped with the default configuration and with four
# small changes of where scans are taken and nodes are made (node every 2.4 / 2.6 m instead of
# 2.5 m, a scan every 0.09 / 0.11 m instead of 0.1 m). None of these should matter; a loop closer
# that accepts a wrong closure or misses a loop shows up as one run far worse than the others.
# Prints the mean and largest relation error of every run and counts the runs above 0.2 m; writes
# output/bench_robustness.json. Figures are measured, never asserted.
# Usage: scripts/bench_robustness.sh [--no-build] [DATASET ...]   (default: intel aces fr079)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="$ROOT/output/bench_robustness"

BUILD=1
DATASETS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) BUILD=0 ;;
    -*) echo "bench_robustness.sh: unknown option '$1'" >&2; exit 2 ;;
    *) DATASETS+=("$1") ;;
  esac
  shift
done
[ ${#DATASETS[@]} -gt 0 ] || DATASETS=(intel aces fr079)
bench_require_data
[ $BUILD -eq 0 ] || bench_build
mkdir -p "$OUT"

VARIANTS=("default" "node_2.4m" "node_2.6m" "scan_0.09m" "scan_0.11m")
variant_yaml() {
  case "$1" in
    default) echo "tracker: {}" ;;
    node_2.4m) echo "tracker: {node_translation_m: 2.4}" ;;
    node_2.6m) echo "tracker: {node_translation_m: 2.6}" ;;
    scan_0.09m) echo "tracker: {min_translation_m: 0.09}" ;;
    scan_0.11m) echo "tracker: {min_translation_m: 0.11}" ;;
  esac
}

for d in "${DATASETS[@]}"; do
  for v in "${VARIANTS[@]}"; do
    variant_yaml "$v" > "$OUT/$v.yaml"
    "$BIN/offline_mapper" --bag "$DATA/$d/$d.bag" --config "$OUT/$v.yaml" \
      --trajectory "$OUT/$d.$v.trajectory.txt" 2> "$OUT/$d.$v.log" > /dev/null
    "$BIN/evaluate_relations" --json --trajectory "$OUT/$d.$v.trajectory.txt" \
      --relations "$DATA/$d/$d.relations" > "$OUT/$d.$v.relations.json"
  done
done

/usr/bin/python3 - "$OUT" "${#VARIANTS[@]}" "${VARIANTS[@]}" "${DATASETS[@]}" <<'PY'
import json, os, sys
out, n = sys.argv[1], int(sys.argv[2])
variants, names = sys.argv[3:3 + n], sys.argv[3 + n:]
rows, failed = [], 0
print("| dataset | " + " | ".join(variants) + " | runs above 0.2 m |")
print("|---|" + "---|" * (len(variants) + 1))
for d in names:
    cells, above = [], 0
    for v in variants:
        r = json.load(open(os.path.join(out, "%s.%s.relations.json" % (d, v))))
        mean, worst = r["trans_abs_mean_m"], r["trans_max_m"]
        above += mean > 0.2
        cells.append("%.3f (max %.2f)" % (mean, worst))
        rows.append({"dataset": d, "variant": v, "trans_err_m": mean, "trans_err_max_m": worst})
    failed += above
    print("| %s | %s | %d of %d |" % (d, " | ".join(cells), above, len(variants)))
json.dump(rows, open(os.path.join(os.path.dirname(out), "bench_robustness.json"), "w"), indent=2)
print("\nmean relation error [m] (largest); %d of %d runs above 0.2 m" % (failed, len(rows)))
print("bench_robustness.sh: wrote %s" % os.path.join(os.path.dirname(out), "bench_robustness.json"))
PY
