#!/usr/bin/env python3
"""Services under load: ~save_map and ~optimize called in loops from two threads while a simulated
bag plays, then ~load_map while scans keep arriving. Every call must answer, every saved file must
be whole (magic, size and CRC-32), and mapping must go on."""
import os
import shutil
import struct
import subprocess
import tempfile
import threading
import time
import unittest
import zlib

import rospy
import rostest
from std_srvs.srv import Trigger

from longterm_mapper2d.msg import MapperStatus
from longterm_mapper2d.srv import LoadMap, SaveMap

BIN_DIR = os.environ.get("LTM_BIN_DIR", "")
WORLD = os.environ.get("LTM_WORLD", "")
FOLDER = "/tmp/ltm_rostest_load_maps"


def check_ltmap(path):
    """Raises unless the file is a whole session map: magic, version, payload size, CRC-32."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"LTMAP2D\n":
        raise AssertionError("bad magic in " + path)
    version, size, crc = struct.unpack("<IQI", data[8:24])
    if len(data) != 24 + size:
        raise AssertionError("%s: %d bytes, header says %d" % (path, len(data), 24 + size))
    if zlib.crc32(data[24:]) & 0xFFFFFFFF != crc:
        raise AssertionError("checksum mismatch in " + path)
    return version


class ServicesUnderLoadTest(unittest.TestCase):
    def test_services_while_mapping(self):
        rospy.init_node("services_under_load_test")
        tmp = tempfile.mkdtemp(prefix="ltm_rostest_load_")
        self.addCleanup(shutil.rmtree, tmp, True)
        subprocess.check_call([os.path.join(BIN_DIR, "simulate_world"), "--world", WORLD, "--out",
                               tmp, "--duration", "120"], stdout=subprocess.DEVNULL)
        statuses = []
        rospy.Subscriber("/mapper_node/status", MapperStatus, statuses.append)
        save = rospy.ServiceProxy("/mapper_node/save_map", SaveMap)
        optimize = rospy.ServiceProxy("/mapper_node/optimize", Trigger)
        load = rospy.ServiceProxy("/mapper_node/load_map", LoadMap)
        for name in ("save_map", "optimize", "load_map"):
            rospy.wait_for_service("/mapper_node/" + name, 30)
        player = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-r", "2",
                                   os.path.join(tmp, "session_1.bag")],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            deadline = time.time() + 60
            while time.time() < deadline and not (statuses and statuses[-1].nodes >= 2):
                time.sleep(0.2)
            self.assertTrue(statuses and statuses[-1].nodes >= 2, "no map built")

            results = {"save": [], "optimize": []}
            stop = threading.Event()

            def saver():
                while not stop.is_set():
                    response = save("under_load")
                    results["save"].append(response.success)
                    if response.success:
                        check_ltmap(os.path.join(FOLDER, "under_load.ltmap"))

            def optimizer():
                while not stop.is_set():
                    results["optimize"].append(optimize().success)

            threads = [threading.Thread(target=saver), threading.Thread(target=optimizer)]
            for t in threads:
                t.start()
            processed = statuses[-1].scans_processed
            time.sleep(15.0)
            stop.set()
            for t in threads:
                t.join(timeout=60)
                self.assertFalse(t.is_alive(), "a service call did not return (deadlock?)")
            print("under load: %d saves, %d optimisations, scans processed %d -> %d" % (
                len(results["save"]), len(results["optimize"]), processed,
                statuses[-1].scans_processed))
            self.assertGreater(len(results["save"]), 2)
            self.assertGreater(len(results["optimize"]), 2)
            self.assertTrue(all(results["save"]))
            self.assertTrue(all(results["optimize"]))
            # Mapping went on meanwhile.
            self.assertGreater(statuses[-1].scans_processed, processed + 20)
            self.assertGreaterEqual(check_ltmap(os.path.join(FOLDER, "under_load.ltmap")), 2)
            for suffix in (".pgm", ".yaml"):
                self.assertTrue(os.path.exists(os.path.join(FOLDER, "under_load" + suffix)))

            # A load while scans arrive: a new session on the saved map, and mapping goes on.
            self.assertEqual(statuses[-1].session_id, 0)
            response = load(path="under_load.ltmap", use_initial_pose=False)
            self.assertTrue(response.success, response.message)
            deadline = time.time() + 30
            while time.time() < deadline and statuses[-1].session_id != 1:
                time.sleep(0.2)
            self.assertEqual(statuses[-1].session_id, 1)
            deadline = time.time() + 30
            while time.time() < deadline and statuses[-1].scans_processed < 20:
                time.sleep(0.2)
            self.assertGreaterEqual(statuses[-1].scans_processed, 20)
            # A failing load (a corrupted copy) answers false and leaves the session as it is.
            with open(os.path.join(FOLDER, "under_load.ltmap"), "rb") as f:
                data = bytearray(f.read())
            data[len(data) // 2] ^= 0xFF
            with open(os.path.join(FOLDER, "corrupted.ltmap"), "wb") as f:
                f.write(data)
            response = load(path="corrupted.ltmap", use_initial_pose=False)
            self.assertFalse(response.success)
            self.assertIn("checksum", response.message)
            time.sleep(1.5)
            self.assertEqual(statuses[-1].session_id, 1)
        finally:
            player.terminate()
            player.wait()


if __name__ == "__main__":
    rostest.rosrun("longterm_mapper2d", "services_under_load_test", ServicesUnderLoadTest)
