// simulate_world: simulated multi-session bags with ground truth, from a world file.
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <sys/stat.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/make_shared.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/io/map_image_io.h"
#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"
#include "longterm_mapper2d/ros/conversions.h"

namespace {

using namespace longterm_mapper2d;  // NOLINT: a small tool

constexpr char kUsage[] = R"(Usage: simulate_world --world FILE.yaml --out DIR [options]

Simulates a robot patrolling a 2D world with people and furniture that changes between sessions,
and writes per session k: DIR/session_k.bag (/scan, /odom, /tf, /tf_static, /ground_truth),
DIR/session_k_truth_trajectory.txt (stamp x y theta) and DIR/session_k_truth.pgm/.yaml (the
static and semi-static world of that session). Deterministic for a seed.

Options:
  --sessions N     number of sessions (default 1)
  --seed S         random seed (default 1)
  --duration S     seconds per session (default 300)
  --beams N        laser beams over the field of view (default 271)
  --fov-deg D      laser field of view in degrees (default 270)
  --laser-x M      the laser this far ahead of the base (default 0.1)
  --interlaced     every other scan starts half a beam later
  --help
)";

geometry_msgs::TransformStamped Stamped(const Pose2& pose, const ros::Time& stamp,
                                        const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = longterm_mapper2d_ros::ToRosTransform(pose);
  return t;
}

sensor_msgs::LaserScan ToRosScan(const LaserScan& scan, const ros::Time& stamp) {
  sensor_msgs::LaserScan msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = scan.frame_id;
  msg.angle_min = scan.angle_min_rad;
  msg.angle_increment = scan.angle_increment_rad;
  msg.angle_max = scan.angle_min_rad + scan.angle_increment_rad * (scan.ranges.size() - 1);
  msg.range_min = scan.range_min_m;
  msg.range_max = scan.range_max_m;
  msg.scan_time = 0.1;
  msg.ranges = scan.ranges;
  return msg;
}

int WriteSession(const World& world, int session, const SimulationOptions& options,
                 std::uint64_t seed, const std::string& out_dir) {
  SessionSimulator simulator(world, session, options, seed + 1000 * session);
  const std::vector<SimulatedStep> steps = simulator.Run();
  const std::string stem = out_dir + "/session_" + std::to_string(session);
  // Bags start at a fixed epoch (ROS time 0 is not allowed), one day per session.
  const double epoch = 1.7e9 + 86400.0 * session;
  std::vector<StampedPose2> truth;
  try {
    rosbag::Bag bag(stem + ".bag", rosbag::bagmode::Write);
    tf2_msgs::TFMessage statics;
    statics.transforms.push_back(
        Stamped(simulator.base_T_laser(), ros::Time(epoch), "base_link", "laser"));
    // Latched, as a live static_transform_publisher is: `rosbag play` then republishes it latched
    // and a node that subscribes after the first message still gets the laser mount.
    auto latched = boost::make_shared<ros::M_string>();
    (*latched)["type"] = ros::message_traits::datatype(statics);
    (*latched)["md5sum"] = ros::message_traits::md5sum(statics);
    (*latched)["message_definition"] = ros::message_traits::definition(statics);
    (*latched)["callerid"] = "/simulate_world";
    (*latched)["latching"] = "1";
    bag.write("/tf_static", ros::Time(epoch), statics, latched);
    for (const SimulatedStep& step : steps) {
      const ros::Time stamp(epoch + step.scan.stamp_s);
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(Stamped(step.odom_T_base, stamp, "odom", "base_link"));
      bag.write("/tf", stamp, tf);
      nav_msgs::Odometry odom;
      odom.header.stamp = stamp;
      odom.header.frame_id = "odom";
      odom.child_frame_id = "base_link";
      const auto t = longterm_mapper2d_ros::ToRosTransform(step.odom_T_base);
      odom.pose.pose.position.x = t.translation.x;
      odom.pose.pose.position.y = t.translation.y;
      odom.pose.pose.orientation = t.rotation;
      bag.write("/odom", stamp, odom);
      bag.write("/scan", stamp, ToRosScan(step.scan, stamp));
      geometry_msgs::PoseStamped gt;
      gt.header.stamp = stamp;
      gt.header.frame_id = "map";
      const auto g = longterm_mapper2d_ros::ToRosTransform(step.map_T_base);
      gt.pose.position.x = g.translation.x;
      gt.pose.position.y = g.translation.y;
      gt.pose.orientation = g.rotation;
      bag.write("/ground_truth", stamp, gt);
      truth.push_back({stamp.toSec(), step.map_T_base});
    }
    bag.close();
  } catch (const std::exception& e) {
    std::cerr << "simulate_world: cannot write " << stem << ".bag: " << e.what() << "\n";
    return 1;
  }
  if (Status s = WriteTrajectory(stem + "_truth_trajectory.txt", truth); !s.ok()) {
    std::cerr << "simulate_world: " << s.message() << "\n";
    return 1;
  }
  if (Status s = WriteMapPgmYaml(RasterizeWorld(world, session, 0.05), stem + "_truth.yaml");
      !s.ok()) {
    std::cerr << "simulate_world: " << s.message() << "\n";
    return 1;
  }
  std::cout << "simulate_world: " << stem << ".bag: " << steps.size() << " scans, "
            << options.duration_s << " s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string world_path, out_dir;
  int sessions = 1;
  std::uint64_t seed = 1;
  SimulationOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "simulate_world: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (arg == "--world") {
      world_path = value();
    } else if (arg == "--out") {
      out_dir = value();
    } else if (arg == "--sessions") {
      sessions = std::atoi(value().c_str());
    } else if (arg == "--seed") {
      seed = std::strtoull(value().c_str(), nullptr, 10);
    } else if (arg == "--duration") {
      options.duration_s = std::atof(value().c_str());
    } else if (arg == "--beams") {
      options.beams = std::atoi(value().c_str());
    } else if (arg == "--fov-deg") {
      options.fov_rad = std::atof(value().c_str()) * M_PI / 180.0;
    } else if (arg == "--laser-x") {
      options.laser_x_m = std::atof(value().c_str());
    } else if (arg == "--interlaced") {
      options.interlaced = true;
    } else {
      std::cerr << "simulate_world: unknown option '" << arg << "'\n\n" << kUsage;
      return 2;
    }
  }
  if (world_path.empty() || out_dir.empty() || sessions < 1) {
    std::cerr << "simulate_world: --world, --out and a positive --sessions are required\n\n"
              << kUsage;
    return 2;
  }
  OptionErrors errors;
  options.Validate(errors);
  if (!errors.empty()) {
    std::cerr << "simulate_world: " << errors.ToString() << "\n";
    return 2;
  }
  auto world = LoadWorld(world_path);
  if (!world.ok()) {
    std::cerr << "simulate_world: " << world.status().message() << "\n";
    return 2;
  }
  ::mkdir(out_dir.c_str(), 0755);
  for (int session = 1; session <= sessions; ++session) {
    if (int code = WriteSession(*world, session, options, seed, out_dir); code != 0) return code;
  }
  return 0;
}
