// reexpress_trajectory: a trajectory written by an earlier session (offline_mapper --anchors),
// in the frame of a later session's map, with every correction the later sessions made.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/core/map/trajectory_anchors.h"

namespace {

constexpr char kUsage[] =
    "usage: reexpress_trajectory --map M.ltmap --anchors A [--anchors A2 ...] --out T\n"
    "                            [--smooth-window-s S]\n"
    "\n"
    "Puts trajectories that offline_mapper wrote with --anchors (each pose in the frame of its\n"
    "local map) into the map frame of M.ltmap, a map that continued the one they were mapped\n"
    "in: local maps merged away since are found through the map's record of removed nodes.\n"
    "  --map M.ltmap  the later session map\n"
    "  --anchors A    an anchored trajectory ('stamp node x y theta [x_w y_w theta_w]' per\n"
    "                 line); repeatable, the poses are written in the order given\n"
    "  --out T        the result, 'stamp x y theta' per line (evaluate_relations reads it)\n"
    "  --smooth-window-s S  smooth each file's poses across local maps again, over the scans\n"
    "                 within S seconds, as the mapper smooths its trajectory (default 8, the\n"
    "                 mapper's trajectory.half_window_s; 0: off; needs the written poses that\n"
    "                 offline_mapper puts in the anchors' last three columns)\n"
    "  --help         show this text\n";

int Fail(const std::string& message) {
  std::fprintf(stderr, "reexpress_trajectory: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace longterm_mapper2d;  // NOLINT: a tool that drives the core
  std::string map_path, out_path;
  double half_window_s = 8.0;
  std::vector<std::string> anchor_paths;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (i + 1 >= argc) return Fail("option " + arg + " needs a value\n\n" + kUsage);
    if (arg == "--map") {
      map_path = argv[++i];
    } else if (arg == "--anchors") {
      anchor_paths.push_back(argv[++i]);
    } else if (arg == "--out") {
      out_path = argv[++i];
    } else if (arg == "--smooth-window-s") {
      const std::string value = argv[++i];
      char* end = nullptr;
      half_window_s = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || *end != '\0' ||
          !(half_window_s >= 0.0 && half_window_s <= 600.0)) {
        return Fail("--smooth-window-s needs a number of seconds in [0, 600], got '" + value + "'");
      }
    } else {
      return Fail("unknown option '" + arg + "'\n\n" + kUsage);
    }
  }
  if (map_path.empty() || anchor_paths.empty() || out_path.empty()) {
    return Fail(std::string("--map, --anchors and --out are required\n\n") + kUsage);
  }
  const auto map = LoadSessionMap(map_path);
  if (!map.ok()) return Fail(map.status().message());
  std::vector<StampedPose2> trajectory;
  for (const std::string& path : anchor_paths) {
    const auto anchors = ReadTrajectoryAnchors(path);
    if (!anchors.ok()) return Fail(anchors.status().message());
    const auto poses = ReexpressTrajectory(*map, *anchors, half_window_s);
    if (!poses.ok()) return Fail(path + ": " + poses.status().message());
    trajectory.insert(trajectory.end(), poses->begin(), poses->end());
  }
  if (const Status s = WriteTrajectory(out_path, trajectory); !s.ok()) return Fail(s.message());
  std::fprintf(stderr, "reexpress_trajectory: %zu poses from %zu files written to %s\n",
               trajectory.size(), anchor_paths.size(), out_path.c_str());
  return 0;
}
