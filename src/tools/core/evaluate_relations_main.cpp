// evaluate_relations: the Kümmerle et al. (2009) relation metric of a trajectory file.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "longterm_mapper2d/core/evaluation/relation_metric.h"
#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/relations_reader.h"
#include "longterm_mapper2d/core/io/trajectory_io.h"

namespace {

using longterm_mapper2d::RelationMetricResult;

constexpr char kUsage[] =
    "usage: evaluate_relations --trajectory T --relations R [--json] [--max-dt S] "
    "[--errors FILE]\n"
    "\n"
    "Evaluates a trajectory (text, one 'stamp x y theta' line per pose, base frame in the map\n"
    "frame) against Kuemmerle et al. relations ('t1 t2 x y z roll pitch yaw' per line).\n"
    "  --trajectory T  trajectory file\n"
    "  --relations R   relations file\n"
    "  --json          print one JSON object instead of the readable summary\n"
    "  --max-dt S      poses are interpolated between neighbours at most S seconds from a\n"
    "                  relation stamp (default 0.1); exact stamps always match\n"
    "  --errors FILE   write 't1 t2 trans_m rot_deg' for every matched relation\n"
    "  --help          show this text\n";

int Fail(const std::string& message) {
  std::fprintf(stderr, "evaluate_relations: %s\n", message.c_str());
  return 1;
}

void PrintJson(const RelationMetricResult& r) {
  std::printf(
      "{\"matched\": %d, \"total\": %d, \"trans_abs_mean_m\": %.9g, \"trans_abs_std_m\": %.9g, "
      "\"trans_sq_mean_m2\": %.9g, \"trans_sq_std_m2\": %.9g, \"trans_max_m\": %.9g, "
      "\"rot_abs_mean_deg\": %.9g, \"rot_abs_std_deg\": %.9g, \"rot_sq_mean_deg2\": %.9g, "
      "\"rot_sq_std_deg2\": %.9g, \"rot_max_deg\": %.9g}\n",
      r.matched, r.total, r.trans_abs_m.mean, r.trans_abs_m.std, r.trans_sq_m2.mean,
      r.trans_sq_m2.std, r.trans_max_m, r.rot_abs_deg.mean, r.rot_abs_deg.std, r.rot_sq_deg2.mean,
      r.rot_sq_deg2.std, r.rot_max_deg);
}

void PrintSummary(const RelationMetricResult& r) {
  std::printf("relations matched:        %d / %d\n", r.matched, r.total);
  std::printf("translational abs [m]:    %.6f +- %.6f  (max %.6f)\n", r.trans_abs_m.mean,
              r.trans_abs_m.std, r.trans_max_m);
  std::printf("translational sq  [m^2]:  %.6f +- %.6f\n", r.trans_sq_m2.mean, r.trans_sq_m2.std);
  std::printf("rotational abs    [deg]:  %.6f +- %.6f  (max %.6f)\n", r.rot_abs_deg.mean,
              r.rot_abs_deg.std, r.rot_max_deg);
  std::printf("rotational sq   [deg^2]:  %.6f +- %.6f\n", r.rot_sq_deg2.mean, r.rot_sq_deg2.std);
}

}  // namespace

int main(int argc, char** argv) {
  std::string trajectory_path, relations_path, errors_path;
  bool json = false;
  longterm_mapper2d::RelationMetricOptions options;
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
    } else if (arg == "--trajectory") {
      if (!value(trajectory_path)) return Fail("--trajectory needs a file");
    } else if (arg == "--relations") {
      if (!value(relations_path)) return Fail("--relations needs a file");
    } else if (arg == "--errors") {
      if (!value(errors_path)) return Fail("--errors needs a file");
    } else if (arg == "--max-dt") {
      std::string text;
      if (!value(text)) return Fail("--max-dt needs a number of seconds");
      char* end = nullptr;
      options.max_dt_s = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0') return Fail("--max-dt: not a number: " + text);
    } else {
      std::fputs(kUsage, stderr);
      return Fail("unknown argument '" + arg + "'");
    }
  }
  if (trajectory_path.empty() || relations_path.empty()) {
    std::fputs(kUsage, stderr);
    return Fail("--trajectory and --relations are required");
  }

  const auto trajectory = longterm_mapper2d::ReadTrajectory(trajectory_path);
  if (!trajectory.ok()) return Fail(trajectory.status().message());
  if (trajectory->empty()) return Fail(trajectory_path + ": no poses");
  const auto relations = longterm_mapper2d::ReadRelations(relations_path);
  if (!relations.ok()) return Fail(relations.status().message());
  if (relations->empty()) return Fail(relations_path + ": no relations");
  const auto result = longterm_mapper2d::EvaluateRelations(*trajectory, *relations, options);
  if (!result.ok()) return Fail(result.status().message());

  if (!errors_path.empty()) {
    std::string text = "# t1 t2 trans_m rot_deg (matched relations only)\n";
    char line[160];
    for (const auto& e : result->errors) {
      if (!e.matched) continue;
      std::snprintf(line, sizeof(line), "%.6f %.6f %.9g %.9g\n", e.t1_s, e.t2_s, e.trans_m,
                    e.rot_deg);
      text += line;
    }
    const auto status = longterm_mapper2d::WriteFileAtomically(errors_path, text);
    if (!status.ok()) return Fail(status.message());
  }
  if (json) {
    PrintJson(*result);
  } else {
    PrintSummary(*result);
  }
  if (result->matched == 0) return Fail("no relation matched the trajectory stamps");
  return 0;
}
