#include "longterm_mapper2d/ros/offline_mapper_app.h"

int main(int argc, char** argv) { return longterm_mapper2d_ros::RunOfflineMapper(argc, argv); }
