#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

struct G2oReadReport {
  std::uint64_t vertices = 0;
  std::uint64_t edges = 0;
  std::uint64_t vertices_initialised_from_edges = 0;  // files without VERTEX lines
  std::map<std::string, std::uint64_t> skipped_tags;
};

// Reads a 2D pose graph: g2o (`VERTEX_SE2 id x y th`, `EDGE_SE2 i j dx dy dth I11 I12 I13 I22 I23
// I33`, `FIX id`) or TORO (`VERTEX2 id x y th`, `EDGE2 i j dx dy dth I11 I12 I22 I33 I13 I23`).
// Nodes without a VERTEX line get an initial pose by composing edges outward from the lowest id.
// A malformed line is an error naming the file and line. Edges are loaded as odometry edges when
// they join consecutive ids, loop closures otherwise.
StatusOr<PoseGraph> ReadG2o(const std::string& path, G2oReadReport* report = nullptr);
StatusOr<PoseGraph> ParseG2o(const std::string& text, const std::string& source_name,
                             G2oReadReport* report = nullptr);

// Writes VERTEX_SE2 / EDGE_SE2 lines and FIX for the gauge; atomic.
Status WriteG2o(const PoseGraph& graph, const std::string& path);
std::string FormatG2o(const PoseGraph& graph);

}  // namespace longterm_mapper2d
