#pragma once

#include <map>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"
#include "longterm_mapper2d/core/mapping/local_map.h"

namespace longterm_mapper2d {

// A local map that maintenance merged away: where it sits in the node that took it over. The
// poses of trajectories written against an earlier map (TrajectoryAnchors) are found through it.
struct RemovedNode {
  NodeId survivor = 0;  // a node of the map (chains are collapsed as nodes go)
  Pose2 survivor_T_removed;
};

// Everything a later session needs: the local maps (pose, cloud, waypoints with their scans),
// the graph edges with their kinds, the gauge, and how many sessions built it.
struct SessionMap {
  int sessions = 0;
  std::map<NodeId, LocalMapNode> nodes;
  std::vector<GraphEdge> edges;
  NodeId gauge = 0;
  // Where the first session started (the docking station), where the map has it when saved: the
  // default start of later sessions. Nodes there may be merged away; the pose follows them.
  Pose2 origin;
  // Every node removed so far, by id (40 bytes each in the file: an intel session removes ~190).
  std::map<NodeId, RemovedNode> removed_nodes;
};

// The session map file (.ltmap), version 6, little-endian:
//   header: "LTMAP2D\n" (8 bytes), uint32 version, uint64 payload size, uint32 CRC-32 of the payload
//   payload: int32 sessions, int64 gauge, origin pose (version 2; version 1 files have none and
//   take the first node's pose), nodes, edges (counts as uint64, values as written by
//   BinaryWriter; poses as x, y, theta doubles; information as its upper triangle). Each waypoint
//   carries its own int32 session after its two poses since version 3 (older files: the node's).
//   Since version 4 the removed nodes follow the edges: a count, then per node int64 id, int64
//   survivor and the pose survivor_T_removed (older files: none). Since version 5 each cloud
//   point's five doubles are followed by a uint8 of flags, bit 0 RichPoint::inherited (older
//   files: 0, every point the node's own). Since version 6 each edge's information is followed
//   by a uint8 (1: it has a gating information, whose upper triangle follows; older files: 0).
// Parsing never trusts a count: one that cannot fit in the remaining bytes is refused before any
// allocation. Serialising a parsed map gives the same bytes.
constexpr std::uint32_t kSessionMapVersion = 6;
std::string SerializeSessionMap(const SessionMap& map);
StatusOr<SessionMap> ParseSessionMap(const std::string& bytes, const std::string& source_name);

// Atomic save (temporary file in the same folder, fsync, rename): the previous file survives any
// failure. Load refuses truncated, corrupted and newer-version files with the reason.
Status SaveSessionMap(const SessionMap& map, const std::string& path);
StatusOr<SessionMap> LoadSessionMap(const std::string& path);

}  // namespace longterm_mapper2d
