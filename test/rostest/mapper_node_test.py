#!/usr/bin/env python3
"""Integration test of mapper_node: a simulated bag played with --clock, then TF, topics, services."""
import os
import shutil
import subprocess
import tempfile
import time
import unittest

import rospy
import rostest
import tf2_ros
import yaml
from nav_msgs.msg import OccupancyGrid
from visualization_msgs.msg import MarkerArray

from longterm_mapper2d.msg import MapperStatus
from diagnostic_msgs.msg import DiagnosticArray
from longterm_mapper2d.srv import SaveMap, SetMode

BIN_DIR = os.environ.get("LTM_BIN_DIR", "")
WORLD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "config", "worlds",
                     "small_room.yaml")


class MapperNodeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("mapper_node_test")
        cls.tmp = tempfile.mkdtemp(prefix="ltm_rostest_")
        world = os.environ.get("LTM_WORLD", WORLD)
        subprocess.check_call([os.path.join(BIN_DIR, "simulate_world"), "--world", world, "--out",
                               cls.tmp, "--duration", "90"])
        cls.status = None
        cls.grid = None
        cls.graph = None
        cls.diagnostics = None
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls._on_diagnostics)
        rospy.Subscriber("/mapper_node/status", MapperStatus, cls._on_status)
        rospy.Subscriber("/map", OccupancyGrid, cls._on_grid)
        rospy.Subscriber("/mapper_node/graph", MarkerArray, cls._on_graph)
        cls.looping = []
        rospy.Subscriber("/looping_node/status", MapperStatus, cls.looping.append)
        cls.player = subprocess.Popen(
            ["rosbag", "play", "--clock", "-q", "-r", "3", os.path.join(cls.tmp, "session_1.bag")],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    @classmethod
    def tearDownClass(cls):
        cls.player.terminate()
        cls.player.wait()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def _on_status(cls, msg):
        cls.status = msg

    @classmethod
    def _on_diagnostics(cls, msg):
        for status in msg.status:
            if status.name.endswith("mapper"):
                cls.diagnostics = status

    @classmethod
    def _on_grid(cls, msg):
        cls.grid = msg

    @classmethod
    def _on_graph(cls, msg):
        cls.graph = msg

    def wait_for(self, condition, timeout_s, what):
        deadline = time.time() + timeout_s
        while time.time() < deadline and not rospy.is_shutdown():
            if condition():
                return
            time.sleep(0.2)
        self.fail("timed out waiting for " + what)

    def cell(self, x, y):
        info = self.grid.info
        ix = int((x - info.origin.position.x) / info.resolution)
        iy = int((y - info.origin.position.y) / info.resolution)
        return self.grid.data[iy * info.width + ix]

    def test_maps_publishes_and_saves(self):
        # The bag plays for 30 s of wall time; wait until the mapper has built a few nodes.
        self.wait_for(lambda: self.status is not None and self.status.nodes >= 5, 120,
                      "~status with 5 nodes")
        self.assertEqual(self.status.session_id, 0)
        self.assertGreater(self.status.scans_processed, 50)

        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        transform = buffer.lookup_transform("map", "odom", rospy.Time(0), rospy.Duration(10.0))
        self.assertEqual(transform.child_frame_id, "odom")

        self.wait_for(lambda: self.grid is not None and self.graph is not None, 30, "/map, ~graph")
        info = self.grid.info
        self.assertAlmostEqual(info.resolution, 0.05, places=5)
        # The room is 8 m x 6 m: the grid covers it and not much more.
        self.assertTrue(7.0 < info.width * info.resolution < 14.0, info.width)
        self.assertTrue(5.0 < info.height * info.resolution < 12.0, info.height)
        # Free where the robot drives; occupied on the walls (within a cell or two).
        self.assertEqual(self.cell(3.0, 1.5), 0)
        wall = [self.cell(4.0, y) for y in (-0.1, -0.05, 0.0, 0.05, 0.1)]
        self.assertIn(100, wall)
        namespaces = {m.ns for m in self.graph.markers}
        self.assertIn("nodes", namespaces)
        self.assertIn("odometry_edges", namespaces)

        save = rospy.ServiceProxy("/mapper_node/save_map", SaveMap)
        rospy.wait_for_service("/mapper_node/save_map", 10)
        response = save("rostest_session")
        self.assertTrue(response.success, response.message)
        for suffix in (".ltmap", ".pgm", ".yaml"):
            self.assertTrue(os.path.exists("/tmp/ltm_rostest_maps/rostest_session" + suffix), suffix)
        with open("/tmp/ltm_rostest_maps/rostest_session.yaml") as f:
            meta = yaml.safe_load(f)
        self.assertAlmostEqual(meta["resolution"], 0.05)
        self.assertEqual(meta["image"], "rostest_session.pgm")

        # A bad path fails cleanly, and the node keeps mapping.
        bad = save("../outside")
        self.assertFalse(bad.success)
        self.assertIn("..", bad.message)
        bad = save("/nonexistent_dir/x")
        self.assertFalse(bad.success)
        before = self.status.scans_received
        self.wait_for(lambda: self.status.scans_received > before, 30, "more scans after a failure")

        # /diagnostics reports the mapper with its counters.
        self.wait_for(lambda: self.diagnostics is not None, 10, "/diagnostics")
        values = {kv.key: kv.value for kv in self.diagnostics.values}
        self.assertEqual(values["mode"], "mapping")
        self.assertGreater(int(values["scans processed"]), 0)

        # Localization freezes the map while scans keep coming; mapping resumes it.
        set_mode = rospy.ServiceProxy("/mapper_node/set_mode", SetMode)
        rospy.wait_for_service("/mapper_node/set_mode", 10)
        self.assertFalse(set_mode("exploring").success)
        response = set_mode("localization")
        self.assertTrue(response.success, response.message)
        self.wait_for(lambda: self.status.mode == "localization", 10, "~status in localization")
        nodes = self.status.nodes
        processed = self.status.scans_processed
        self.wait_for(lambda: self.status.scans_processed > processed + 20, 30,
                      "scans tracked in localization")
        self.assertEqual(self.status.nodes, nodes)
        response = set_mode("mapping")
        self.assertTrue(response.success, response.message)
        self.wait_for(lambda: self.status.mode == "mapping", 10, "~status back in mapping")

        # A second node started on the saved map continues it as session 1 and ties into it,
        # fed by the bag played again (the first node refuses the replay: time went backwards).
        saved_nodes = self.status.nodes
        self.assertTrue(self.looping and self.looping[-1].session_id == 0)
        looping_nodes = self.looping[-1].nodes
        second_status = []
        rospy.Subscriber("/mapper_node2/status", MapperStatus, second_status.append)
        # The first play ends before the second node starts: a scan it saw would set its clock.
        self.player.wait(timeout=120)
        second = subprocess.Popen(
            [os.path.join(BIN_DIR, "mapper_node"), "__name:=mapper_node2", "map:=map2",
             "map_metadata:=map_metadata2", "_load_map:=/tmp/ltm_rostest_maps/rostest_session.ltmap",
             "_map_folder:=/tmp/ltm_rostest_maps", "_scan_topic:=/scan",
             "_map_update_interval_s:=1.0"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            self.wait_for(lambda: second_status and second_status[-1].session_id == 1, 30,
                          "the second node's ~status")
            replay = subprocess.Popen(
                ["rosbag", "play", "--clock", "-q", "-r", "3",
                 os.path.join(self.tmp, "session_1.bag")],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            try:
                self.wait_for(lambda: second_status[-1].scans_processed > 100 and
                              second_status[-1].loop_closures_accepted + second_status[-1].merges > 0,
                              120, "the second session to close loops with the first")
            finally:
                replay.terminate()
                replay.wait()
            last = second_status[-1]
            self.assertEqual(last.session_id, 1)
            self.assertGreaterEqual(last.nodes + last.nodes_removed, saved_nodes)
            # time_backwards "refuse" (the first node) stays in session 0; "new_session" (the
            # looping node) went on as session 1 on its own map, which it still holds.
            self.assertEqual(self.status.session_id, 0)
            self.assertGreater(self.status.scans_skipped, 0)
            self.wait_for(lambda: self.looping[-1].session_id == 1 and
                          self.looping[-1].scans_processed > 50, 30, "the looping node's session 1")
            self.assertGreaterEqual(self.looping[-1].nodes + self.looping[-1].nodes_removed,
                                    looping_nodes)
        finally:
            second.terminate()
            second.wait()


if __name__ == "__main__":
    rostest.rosrun("longterm_mapper2d", "mapper_node_test", MapperNodeTest)
