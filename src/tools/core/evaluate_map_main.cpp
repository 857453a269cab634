// evaluate_map: occupied-cell precision, recall and phantoms of a map against a ground-truth map.
#include <cstdio>
#include <string>

#include "longterm_mapper2d/core/evaluation/map_comparison.h"
#include "longterm_mapper2d/core/io/map_image_io.h"

namespace {

constexpr char kUsage[] =
    "usage: evaluate_map --map M.yaml --truth T.yaml [--json] [--diff OUT.png]\n"
    "\n"
    "Compares two map_server maps (YAML + PGM) of the same map frame on the truth's cells\n"
    "(the map is resampled if its resolution or origin differ).\n"
    "  precision = occupied map cells within one cell of a true occupied cell / occupied map "
    "cells\n"
    "  recall    = true occupied cells observed by the map and within one cell of an occupied\n"
    "              map cell / true occupied cells observed by the map\n"
    "  phantoms  = occupied map cells more than two cells from every true occupied cell\n"
    "  --json        print one JSON object instead of the readable summary\n"
    "  --diff F.png  write the comparison image: correct green, phantom red, missed blue,\n"
    "                never-observed true cells light blue, near misses orange\n"
    "  --help        show this text\n";

int Fail(const std::string& message) {
  std::fprintf(stderr, "evaluate_map: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string map_path, truth_path, diff_path;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc) return false;
      out = argv[++i];
      return true;
    };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--json") {
      json = true;
    } else if (arg == "--map") {
      if (!value(map_path)) return Fail("--map needs a YAML file");
    } else if (arg == "--truth") {
      if (!value(truth_path)) return Fail("--truth needs a YAML file");
    } else if (arg == "--diff") {
      if (!value(diff_path)) return Fail("--diff needs a PNG file");
    } else {
      std::fputs(kUsage, stderr);
      return Fail("unknown argument '" + arg + "'");
    }
  }
  if (map_path.empty() || truth_path.empty()) {
    std::fputs(kUsage, stderr);
    return Fail("--map and --truth are required");
  }
  const auto map = longterm_mapper2d::ReadMapPgmYaml(map_path);
  if (!map.ok()) return Fail(map.status().message());
  const auto truth = longterm_mapper2d::ReadMapPgmYaml(truth_path);
  if (!truth.ok()) return Fail(truth.status().message());

  longterm_mapper2d::RgbImage diff;
  const auto result =
      longterm_mapper2d::CompareMaps(*map, *truth, {}, diff_path.empty() ? nullptr : &diff);
  if (!result.ok()) return Fail(result.status().message());
  if (!diff_path.empty()) {
    const auto status = longterm_mapper2d::WritePng(diff, diff_path);
    if (!status.ok()) return Fail(status.message());
  }
  const auto& r = *result;
  if (json) {
    std::printf(
        "{\"precision\": %.9g, \"recall\": %.9g, \"phantom_cells\": %lld, "
        "\"phantom_fraction\": %.9g, \"map_occupied\": %lld, \"correct\": %lld, "
        "\"on_truth\": %lld, \"precision_on_truth\": %.9g, "
        "\"truth_occupied\": %lld, \"truth_observed\": %lld, \"recalled\": %lld}\n",
        r.precision, r.recall, static_cast<long long>(r.phantom), r.phantom_fraction,
        static_cast<long long>(r.map_occupied), static_cast<long long>(r.correct),
        static_cast<long long>(r.on_truth), r.precision_on_truth,
        static_cast<long long>(r.truth_occupied), static_cast<long long>(r.truth_observed),
        static_cast<long long>(r.recalled));
  } else {
    std::printf("occupied map cells:       %lld (%lld within one cell of the truth)\n",
                static_cast<long long>(r.map_occupied), static_cast<long long>(r.correct));
    std::printf("precision:                %.4f\n", r.precision);
    std::printf("on a true cell itself:    %lld (%.4f of the occupied map cells)\n",
                static_cast<long long>(r.on_truth), r.precision_on_truth);
    std::printf("true occupied cells:      %lld (%lld observed by the map, %lld recalled)\n",
                static_cast<long long>(r.truth_occupied), static_cast<long long>(r.truth_observed),
                static_cast<long long>(r.recalled));
    std::printf("recall:                   %.4f\n", r.recall);
    std::printf("phantom cells:            %lld (%.4f of the occupied map cells)\n",
                static_cast<long long>(r.phantom), r.phantom_fraction);
  }
  return 0;
}
