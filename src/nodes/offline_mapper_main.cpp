// offline_mapper with ROS bag input: the core's offline mapper, given a reader for bags.
#include <memory>
#include <string>
#include <vector>

#include "longterm_mapper2d/ros/bag_scan_source.h"
#include "longterm_mapper2d/tools/offline_mapper_app.h"

namespace {

using longterm_mapper2d::RecordedScans;
using longterm_mapper2d::RecordingOptions;
using longterm_mapper2d::Status;
using longterm_mapper2d::StatusOr;
using longterm_mapper2d_ros::BagScanSource;

class BagRecording : public RecordedScans {
 public:
  explicit BagRecording(std::unique_ptr<BagScanSource> source) : source_(std::move(source)) {}
  std::uint64_t scan_count() const override { return source_->scan_count(); }
  Status ForEach(const std::function<void(const longterm_mapper2d::ScanInput&)>& visit) override {
    return source_->ForEach(visit);
  }
  std::uint64_t scans_without_odometry() const override {
    return source_->stats().scans_without_odometry;
  }
  std::vector<std::string> warnings() const override { return source_->warnings(); }

 private:
  std::unique_ptr<BagScanSource> source_;
};

StatusOr<std::unique_ptr<RecordedScans>> OpenBags(const std::vector<std::string>& paths,
                                                  const RecordingOptions& recording) {
  longterm_mapper2d_ros::BagReaderOptions options;
  options.scan_topic = recording.scan_topic;
  options.odom_frame = recording.odom_frame;
  options.base_frame = recording.base_frame;
  options.odom_topic = recording.odom_topic;
  options.start_s = recording.start_s;
  options.end_s = recording.end_s;
  auto source = BagScanSource::Open(paths, options);
  if (!source.ok()) return source.status();
  return std::unique_ptr<RecordedScans>(std::make_unique<BagRecording>(std::move(*source)));
}

}  // namespace

int main(int argc, char** argv) {
  return longterm_mapper2d::RunOfflineMapper(argc, argv, OpenBags);
}
