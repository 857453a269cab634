// optimize_graph: optimises a 2D pose graph file (g2o or TORO) with the project's Ceres back end.
#include <cstdlib>
#include <iostream>
#include <string>

#include "longterm_mapper2d/core/graph/optimizer.h"
#include "longterm_mapper2d/core/io/g2o_io.h"
#include "longterm_mapper2d/core/io/json_writer.h"

namespace {

constexpr char kUsage[] = R"(Usage: optimize_graph IN.g2o [OUT.g2o] [options]

Loads a 2D pose graph (g2o VERTEX_SE2/EDGE_SE2/FIX, or TORO VERTEX2/EDGE2), optimises it with
Levenberg-Marquardt (Ceres, sparse Cholesky on SuiteSparse) from the file's initial estimate, and
prints the initial and final chi2, iterations and time. Writes the result to OUT.g2o if given.

Options:
  --max-iterations N   default 100
  --robust             Cauchy loss on loop closures (edges between non-consecutive ids)
  --json               print one JSON object instead of text
  --help
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace longterm_mapper2d;  // NOLINT: a small tool
  std::string in_path, out_path;
  bool json = false;
  OptimizerOptions options;
  options.max_iterations = 100;
  options.loop_closure_loss_scale = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (arg == "--json") {
      json = true;
    } else if (arg == "--robust") {
      options.loop_closure_loss_scale = 3.0;
    } else if (arg == "--max-iterations" && i + 1 < argc) {
      options.max_iterations = std::atoi(argv[++i]);
    } else if (!arg.empty() && arg[0] == '-') {
      std::cerr << "optimize_graph: unknown option '" << arg << "'\n\n" << kUsage;
      return 2;
    } else if (in_path.empty()) {
      in_path = arg;
    } else if (out_path.empty()) {
      out_path = arg;
    } else {
      std::cerr << "optimize_graph: too many arguments\n\n" << kUsage;
      return 2;
    }
  }
  if (in_path.empty() || options.max_iterations < 1) {
    std::cerr << kUsage;
    return 2;
  }
  G2oReadReport report;
  auto graph = ReadG2o(in_path, &report);
  if (!graph.ok()) {
    std::cerr << "optimize_graph: " << graph.status().message() << "\n";
    return 2;
  }
  const OptimizationSummary summary = Optimize(*graph, options);
  if (json) {
    JsonObject out;
    out.Add("file", in_path)
        .Add("nodes", static_cast<std::uint64_t>(graph->nodes().size()))
        .Add("edges", static_cast<std::uint64_t>(graph->edges().size()))
        .Add("initial_chi2", summary.initial_chi2)
        .Add("final_chi2", summary.final_chi2)
        .Add("iterations", summary.iterations)
        .Add("time_s", summary.time_s)
        .Add("usable", summary.usable);
    std::cout << out.ToString() << "\n";
  } else {
    std::cout << in_path << ": " << graph->nodes().size() << " nodes, " << graph->edges().size()
              << " edges";
    if (report.vertices_initialised_from_edges > 0) {
      std::cout << " (" << report.vertices_initialised_from_edges
                << " nodes initialised from the edges)";
    }
    std::cout << "\ninitial chi2: " << summary.initial_chi2 << "\nfinal chi2:   "
              << summary.final_chi2 << "\niterations:   " << summary.iterations
              << "\ntime [s]:     " << summary.time_s << "\n";
    if (!summary.usable) std::cout << "the solution is not usable: " << summary.message << "\n";
  }
  if (!out_path.empty()) {
    if (Status s = WriteG2o(*graph, out_path); !s.ok()) {
      std::cerr << "optimize_graph: " << s.message() << "\n";
      return 1;
    }
  }
  return summary.usable ? 0 : 1;
}
