#include "longterm_mapper2d/tools/offline_mapper_app.h"

#include <malloc.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/config/yaml_options.h"
#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/carmen_reader.h"
#include "longterm_mapper2d/core/io/json_writer.h"
#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/core/map/trajectory_anchors.h"
#include "longterm_mapper2d/core/mapping/map_outputs.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/tools/progress_reporter.h"
#include "longterm_mapper2d/tools/scan_prefetcher.h"

namespace longterm_mapper2d {

namespace {

constexpr char kUsage[] =
    R"(Usage: offline_mapper (--bag FILE [--bag FILE ...] | --carmen FILE) [options]

Maps recorded data with the same core as mapper_node, much faster than real time.

Input:
  --bag FILE            a ROS bag (repeatable; the bags are read as one recording; not in a
                        ROS-free build, LTM_CORE_ONLY)
  --carmen FILE         a CARMEN log (FLASER, ROBOTLASER1, ODOM)
  --scan-topic TOPIC    sensor_msgs/LaserScan topic in the bags (default /scan)
  --odom-frame FRAME    odometry frame in /tf (default odom)
  --base-frame FRAME    robot base frame in /tf (default base_link)
  --odom-topic TOPIC    take odometry from this nav_msgs/Odometry topic instead of /tf
  --start S, --end S    only the data from S to E seconds after the first message
  --laser-mount X,Y,TH  where the laser sits on the base, replacing what the recording says
                        (its base -> laser transform, or a CARMEN log's pose difference): for a
                        recording whose mount is known to be wrong
Configuration:
  --config FILE.yaml    mapper options (see config/mapping.yaml); unknown keys are errors
  --print-config        print the effective options as YAML and exit
Sessions:
  --load-map FILE.ltmap   start a new session on top of a saved map
  --initial-pose X,Y,TH   the robot's pose in the loaded map at the first scan (default: where the
                          map's first session started, the docking-station case)
  --save-map FILE.ltmap   save the session map at the end (atomic)
  --no-maintenance        keep every node (no merging of revisited local maps), for comparison
Output:
  --trajectory FILE     `stamp x y theta` per input scan: base in the map frame, final estimate
  --anchors FILE        `stamp node x y theta x_w y_w theta_w` per input scan: base in its
                        local map's frame (and in the map frame, as written); reexpress_trajectory
                        puts it in a later session's map
  --stats FILE.json     scans read/processed/skipped, wall time, peak RSS, time per stage
  --output-dir DIR      map.pgm/map.yaml/map.png, trajectory.txt and stats.json in DIR
  --help                this text
)";

struct Arguments {
  std::vector<std::string> bags;
  std::string carmen;
  std::string config;
  std::string trajectory;
  std::string anchors;
  std::string stats;
  std::string output_dir;
  std::string load_map;
  std::string save_map;
  std::optional<Pose2> initial_pose;
  std::optional<Pose2> laser_mount;
  bool print_config = false;
  bool no_maintenance = false;
  RecordingOptions bag;
};

// Parses the command line; returns an error message, or empty on success.
std::string Parse(int argc, char** argv, Arguments& args, bool& help) {
  auto need_value = [&](int& i, std::string& out) -> bool {
    if (i + 1 >= argc) return false;
    out = argv[++i];
    return true;
  };
  auto need_number = [&](int& i, double& out) -> bool {
    std::string text;
    if (!need_value(i, text)) return false;
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end != text.c_str() && *end == '\0';
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    std::string value;
    bool ok = true;
    if (arg == "--help" || arg == "-h") {
      help = true;
    } else if (arg == "--bag") {
      ok = need_value(i, value);
      args.bags.push_back(value);
    } else if (arg == "--carmen") {
      ok = need_value(i, args.carmen);
    } else if (arg == "--config") {
      ok = need_value(i, args.config);
    } else if (arg == "--trajectory") {
      ok = need_value(i, args.trajectory);
    } else if (arg == "--anchors") {
      ok = need_value(i, args.anchors);
    } else if (arg == "--stats") {
      ok = need_value(i, args.stats);
    } else if (arg == "--output-dir") {
      ok = need_value(i, args.output_dir);
    } else if (arg == "--scan-topic") {
      ok = need_value(i, args.bag.scan_topic);
    } else if (arg == "--odom-frame") {
      ok = need_value(i, args.bag.odom_frame);
    } else if (arg == "--base-frame") {
      ok = need_value(i, args.bag.base_frame);
    } else if (arg == "--odom-topic") {
      ok = need_value(i, args.bag.odom_topic);
    } else if (arg == "--start") {
      ok = need_number(i, args.bag.start_s);
    } else if (arg == "--end") {
      ok = need_number(i, args.bag.end_s);
    } else if (arg == "--load-map") {
      ok = need_value(i, args.load_map);
    } else if (arg == "--save-map") {
      ok = need_value(i, args.save_map);
    } else if (arg == "--initial-pose" || arg == "--laser-mount") {
      double x, y, theta;
      char extra;
      ok = need_value(i, value) &&
           std::sscanf(value.c_str(), "%lf,%lf,%lf%c", &x, &y, &theta, &extra) == 3 &&
           std::isfinite(x) && std::isfinite(y) && std::isfinite(theta);
      if (ok) (arg == "--laser-mount" ? args.laser_mount : args.initial_pose) = Pose2(x, y, theta);
    } else if (arg == "--print-config") {
      args.print_config = true;
    } else if (arg == "--no-maintenance") {
      args.no_maintenance = true;
    } else {
      return "unknown option '" + arg + "'";
    }
    if (!ok) return "option " + arg + " needs a valid value";
  }
  if (help || args.print_config) return "";
  if (args.bags.empty() == args.carmen.empty()) return "give either --bag FILE(s) or --carmen FILE";
  if (args.bag.end_s >= 0.0 && args.bag.end_s <= args.bag.start_s) {
    return "--end must be after --start";
  }
  if (args.initial_pose && args.load_map.empty()) return "--initial-pose needs --load-map";
  return "";
}

double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

JsonObject GraphJson(const PoseGraph& graph) {
  std::uint64_t per_kind[3] = {0, 0, 0};
  for (const GraphEdge& edge : graph.edges()) ++per_kind[static_cast<int>(edge.kind)];
  JsonObject json;
  json.Add("nodes", static_cast<std::uint64_t>(graph.nodes().size()))
      .Add("edges_odometry", per_kind[0])
      .Add("edges_loop_closure", per_kind[1])
      .Add("edges_condensed", per_kind[2]);
  return json;
}

JsonObject StatsJson(const Mapper& mapper, double wall_s, double data_duration_s,
                     const std::string& source, const StageTimes& io_times,
                     std::uint64_t scans_read, std::uint64_t scans_without_odometry) {
  const MapperStats& stats = mapper.stats();
  JsonObject skipped;
  for (const auto& [reason, count] : stats.scans_skipped) skipped.Add(reason, count);
  if (scans_without_odometry > 0) skipped.Add("no_odometry", scans_without_odometry);
  JsonObject counters;
  for (const auto& [name, count] : stats.counters) counters.Add(name, count);
  JsonObject stages;
  for (const auto& [stage, seconds] : io_times.seconds()) stages.Add(stage, seconds);
  for (const auto& [stage, seconds] : stats.stage_times.seconds()) stages.Add(stage, seconds);
  JsonObject json;
  json.Add("source", source)
      .Add("scans_read", scans_read)
      .Add("scans_processed", stats.scans_processed)
      .Add("scans_skipped", stats.TotalSkipped() + scans_without_odometry)
      .Add("skipped_by_reason", skipped)
      .Add("counters", counters)
      .Add("data_duration_s", data_duration_s)
      .Add("wall_time_s", wall_s)
      .Add("real_time_factor", wall_s > 0 ? data_duration_s / wall_s : 0.0)
      .Add("session_id", mapper.session_id())
      .Add("graph", GraphJson(mapper.graph()))
      .Add("peak_rss_mb", PeakRssMb())
      .Add("stage_time_s", stages);
  return json;
}

}  // namespace

int RunOfflineMapper(int argc, char** argv, const RecordingOpener& open_bags) {
#ifdef __GLIBC__
  // One malloc arena for the process: the bag-reading thread's allocations otherwise stay in an
  // arena of their own once freed (peak RSS 245 instead of 160 MB on an hour of the simulated
  // care home, at the same speed).
  mallopt(M_ARENA_MAX, 1);
#endif
  Arguments args;
  bool help = false;
  if (const std::string error = Parse(argc, argv, args, help); !error.empty()) {
    std::cerr << "offline_mapper: " << error << "\n\n" << kUsage;
    return 2;
  }
  if (help) {
    std::cout << kUsage;
    return 0;
  }
  if (!args.bags.empty() && !open_bags) {
    std::cerr << "offline_mapper: this build reads no ROS bags (built without ROS, LTM_CORE_ONLY); "
                 "give a CARMEN log with --carmen FILE\n";
    return 2;
  }
  MapperOptions options;
  if (!args.config.empty()) {
    if (Status s = LoadMapperOptions(args.config, options); !s.ok()) {
      std::cerr << "offline_mapper: invalid configuration " << s.message() << "\n";
      return 2;
    }
  }
  if (args.no_maintenance) options.maintenance.enabled = false;
  if (args.print_config) {
    std::cout << OptionsToYaml(options) << "\n";
    return 0;
  }

  const auto wall_start = std::chrono::steady_clock::now();
  StageTimes io_times;
  Mapper mapper(options);
  if (!args.load_map.empty()) {
    auto loaded = LoadSessionMap(args.load_map);
    if (!loaded.ok()) {
      std::cerr << "offline_mapper: " << loaded.status().message() << "\n";
      return 2;
    }
    if (Status s = mapper.LoadSession(*loaded, args.initial_pose); !s.ok()) {
      std::cerr << "offline_mapper: " << s.message() << "\n";
      return 2;
    }
  }
  std::uint64_t scans_read = 0, scans_without_odometry = 0;
  double first_stamp = 0.0, last_stamp = 0.0;
  auto feed = [&](const ScanInput& input, ProgressReporter& progress) {
    if (scans_read == 0) first_stamp = input.scan.stamp_s;
    last_stamp = input.scan.stamp_s;
    ++scans_read;
    if (args.laser_mount) {
      ScanInput mounted = input;
      mounted.base_T_laser = *args.laser_mount;
      mapper.AddScan(mounted);
    } else {
      mapper.AddScan(input);
    }
    progress.Update(scans_read);
  };

  std::string source;
  if (!args.carmen.empty()) {
    source = args.carmen;
    StatusOr<CarmenLog> log = Status::Error("not read");
    {
      ScopedStageTimer timer(io_times, "reading");
      log = ReadCarmenLog(args.carmen);
    }
    if (!log.ok()) {
      std::cerr << "offline_mapper: " << log.status().message() << "\n";
      return 2;
    }
    ProgressReporter progress(log->scans.size());
    for (const ScanInput& input : log->scans) {
      const double t = input.scan.stamp_s - (log->scans.front().scan.stamp_s);
      if (t < args.bag.start_s || (args.bag.end_s >= 0.0 && t >= args.bag.end_s)) continue;
      feed(input, progress);
    }
    progress.Finish();
  } else {
    for (const auto& bag : args.bags) source += (source.empty() ? "" : ",") + bag;
    StatusOr<std::unique_ptr<RecordedScans>> bags = Status::Error("not read");
    {
      ScopedStageTimer timer(io_times, "reading_odometry");
      bags = open_bags(args.bags, args.bag);
    }
    if (!bags.ok()) {
      std::cerr << "offline_mapper: " << bags.status().message() << "\n";
      return 2;
    }
    for (const auto& warning : (*bags)->warnings()) {
      std::cerr << "offline_mapper: warning: " << warning << "\n";
    }
    ProgressReporter progress((*bags)->scan_count());
    // Decoding the bags (bz2) overlaps with mapping; the scans arrive in the same order.
    const Status read =
        ForEachPrefetched(**bags, [&](const ScanInput& input) { feed(input, progress); });
    progress.Finish();
    if (!read.ok()) {
      std::cerr << "offline_mapper: " << read.message() << "\n";
      return 2;
    }
    scans_without_odometry = (*bags)->scans_without_odometry();
  }
  mapper.Finish();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  JsonObject stats = StatsJson(mapper, wall_s, last_stamp - first_stamp, source, io_times,
                               scans_read, scans_without_odometry);

  int exit_code = 0;
  auto report = [&](const Status& s) {
    if (!s.ok()) {
      std::cerr << "offline_mapper: " << s.message() << "\n";
      exit_code = 1;
    }
  };
  if (!args.save_map.empty()) {
    const Status saved = SaveSessionMap(mapper.ExportSession(), args.save_map);
    report(saved);
    struct stat info {};
    if (saved.ok() && ::stat(args.save_map.c_str(), &info) == 0) {
      stats.Add("map_file_bytes", static_cast<std::uint64_t>(info.st_size));
    }
  }
  if (!args.trajectory.empty()) report(WriteTrajectory(args.trajectory, mapper.Trajectory()));
  if (!args.anchors.empty()) {
    report(WriteTrajectoryAnchors(args.anchors, mapper.TrajectoryAnchors()));
  }
  if (!args.stats.empty()) report(WriteFileAtomically(args.stats, stats.ToString() + "\n"));
  if (!args.output_dir.empty()) {
    report(WriteMapOutputs(mapper, args.output_dir));
    report(WriteFileAtomically(args.output_dir + "/stats.json", stats.ToString() + "\n"));
  }
  const MapperStats& s = mapper.stats();
  std::fprintf(stderr,
               "offline_mapper: %llu scans read, %llu processed, %llu skipped, %.1f s of data in "
               "%.2f s (%.0fx real time), peak RSS %.0f MB\n",
               static_cast<unsigned long long>(scans_read),
               static_cast<unsigned long long>(s.scans_processed),
               static_cast<unsigned long long>(s.TotalSkipped() + scans_without_odometry),
               last_stamp - first_stamp, wall_s,
               wall_s > 0 ? (last_stamp - first_stamp) / wall_s : 0.0, PeakRssMb());
  return exit_code;
}

}  // namespace longterm_mapper2d
