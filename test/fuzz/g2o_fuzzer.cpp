// Fuzzes ParseG2o (g2o and TORO pose-graph text). Malformed input must give an error, never a
// crash or UB. A graph that parses goes to the optimizer, so every edge must join two distinct
// existing nodes, all poses and information matrices must be finite and the gauge must exist;
// and what FormatG2o writes of it must read back with the same nodes and edges.
#include <cstddef>
#include <cstdint>
#include <string>

#include "longterm_mapper2d/core/io/g2o_io.h"

namespace longterm_mapper2d {
namespace {

void Check(bool condition) {
  if (!condition) __builtin_trap();
}

void FuzzOne(const std::string& text) {
  G2oReadReport report;
  const StatusOr<PoseGraph> graph = ParseG2o(text, "fuzz.g2o", &report);
  if (!graph.ok()) {
    Check(!graph.status().message().empty());
    return;
  }
  for (const auto& [id, node] : graph->nodes()) {
    Check(node.id == id);
    Check(node.pose.IsFinite());
  }
  for (const GraphEdge& edge : graph->edges()) {
    Check(graph->HasNode(edge.from) && graph->HasNode(edge.to));
    Check(edge.from != edge.to);
    Check(edge.measurement.IsFinite());
    Check(edge.information.allFinite());
  }
  Check(graph->edges().size() == report.edges);
  Check(graph->nodes().empty() || (graph->gauge() && graph->HasNode(*graph->gauge())));

  const StatusOr<PoseGraph> again = ParseG2o(FormatG2o(*graph), "formatted.g2o");
  Check(again.ok());
  Check(again->nodes().size() == graph->nodes().size());
  Check(again->edges().size() == graph->edges().size());
}

}  // namespace
}  // namespace longterm_mapper2d

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  longterm_mapper2d::FuzzOne(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
