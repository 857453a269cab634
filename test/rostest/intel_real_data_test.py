#!/usr/bin/env python3
"""Real-data tier: mapper_node on intel.bag (rosbag play --clock -r 10) against offline_mapper.

The node's final trajectory (map -> base_link at each scan, as published on ~trajectory after a
last ~optimize) must score a mean translational relation error within 20% of offline_mapper's on
the same bag, with the same options, and the node must drop no scan.
"""
import json
import math
import os
import shutil
import subprocess
import tempfile
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Path
from std_srvs.srv import Trigger

from longterm_mapper2d.msg import MapperStatus

BIN_DIR = os.environ.get("LTM_BIN_DIR", "")
DATA_DIR = os.environ.get("LTM_DATA_DIR", "")
CONFIG_DIR = os.environ.get("LTM_CONFIG_DIR", "")
RATE = os.environ.get("LTM_PLAY_RATE", "10")


def relation_error(trajectory_path, relations_path):
    out = subprocess.check_output([os.path.join(BIN_DIR, "evaluate_relations"), "--json",
                                   "--trajectory", trajectory_path, "--relations", relations_path])
    return json.loads(out)


class IntelNodeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("intel_real_data_test")
        cls.tmp = tempfile.mkdtemp(prefix="ltm_rostest_intel_")
        cls.bag = os.path.join(DATA_DIR, "intel", "intel.bag")
        cls.relations = os.path.join(DATA_DIR, "intel", "intel.relations")
        cls.status = None
        cls.path = None
        cls.path_received_wall = 0.0
        rospy.Subscriber("/mapper_node/status", MapperStatus, cls._on_status)
        rospy.Subscriber("/mapper_node/trajectory", Path, cls._on_path)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_status(cls, msg):
        cls.status = msg

    @classmethod
    def _on_path(cls, msg):
        cls.path = msg
        cls.path_received_wall = time.time()

    def wait_for(self, condition, timeout_s, what):
        deadline = time.time() + timeout_s
        while time.time() < deadline and not rospy.is_shutdown():
            if condition():
                return
            time.sleep(0.5)
        self.fail("timed out waiting for " + what)

    def write_path(self, path, file_name):
        with open(file_name, "w") as f:
            for pose in path.poses:
                q = pose.pose.orientation
                theta = 2.0 * math.atan2(q.z, q.w)
                f.write("%.6f %.6f %.6f %.6f\n" % (pose.header.stamp.to_sec(), pose.pose.position.x,
                                                   pose.pose.position.y, theta))

    def test_node_matches_offline_mapper(self):
        self.assertTrue(os.path.isfile(self.bag), "no bag at " + self.bag)
        # The reference: offline_mapper, same bag, same options.
        offline_trajectory = os.path.join(self.tmp, "offline.trajectory.txt")
        subprocess.check_call([os.path.join(BIN_DIR, "offline_mapper"), "--bag", self.bag,
                               "--config", os.path.join(CONFIG_DIR, "mapping.yaml"),
                               "--trajectory", offline_trajectory],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        offline = relation_error(offline_trajectory, self.relations)

        started = time.time()
        subprocess.check_call(["rosbag", "play", "--clock", "-q", "--delay=2", "-r", RATE, self.bag],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        played_s = time.time() - started
        # The worker drains its queue: the count of scans handed to the mapper stops moving.
        self.wait_for(lambda: self.status is not None, 30, "~status")
        last = (-1, time.time())
        while time.time() - last[1] < 5.0:
            received = self.status.scans_received
            if received != last[0]:
                last = (received, time.time())
            time.sleep(0.5)
        optimize = rospy.ServiceProxy("/mapper_node/optimize", Trigger)
        optimize.wait_for_service(30)
        response = optimize()
        self.assertTrue(response.success, response.message)
        asked = time.time()
        self.wait_for(lambda: self.path_received_wall > asked and self.status is not None,
                      60, "~trajectory after ~optimize")
        node_trajectory = os.path.join(self.tmp, "node.trajectory.txt")
        self.write_path(self.path, node_trajectory)
        node = relation_error(node_trajectory, self.relations)

        status = self.status
        print("intel at -r %s: played in %.0f s; scans received %d, dropped %d; poses %d; "
              "relation error node %.3f m / %.2f deg (max %.2f m), offline %.3f m / %.2f deg "
              "(max %.2f m)" % (RATE, played_s, status.scans_received, status.scans_dropped_no_tf,
                                len(self.path.poses), node["trans_abs_mean_m"],
                                node["rot_abs_mean_deg"], node["trans_max_m"],
                                offline["trans_abs_mean_m"], offline["rot_abs_mean_deg"],
                                offline["trans_max_m"]))
        self.assertEqual(status.scans_dropped_no_tf, 0)
        self.assertGreater(status.scans_received, 13000)  # intel.bag holds 13631 scans
        self.assertGreater(len(self.path.poses), 13000)
        self.assertLessEqual(node["trans_abs_mean_m"], 1.2 * offline["trans_abs_mean_m"])


if __name__ == "__main__":
    rostest.rosrun("longterm_mapper2d", "intel_real_data_test", IntelNodeTest)
