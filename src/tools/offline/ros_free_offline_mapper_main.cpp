// offline_mapper in the ROS-free build (LTM_CORE_ONLY): CARMEN logs only.
#include "longterm_mapper2d/tools/offline_mapper_app.h"

int main(int argc, char** argv) { return longterm_mapper2d::RunOfflineMapper(argc, argv, {}); }
