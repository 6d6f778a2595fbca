#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Publishes a recorded vehicle trajectory as nav_msgs/Odometry on /odom, paced in real time
(times --rate), for the live node sonarsynth_ros (docs/robotics.md, "The live ROS 1 node").

The CSV has a header line and the columns stamp_s, x_m, y_m, z_m, yaw_rad, pitch_rad, roll_rad,
speed_m_s: base_link in the odom frame (the scene's local frame: x grid east, y grid north,
z up; REP 103 angles: yaw counter-clockwise from east, pitch + nose down, roll + port up).
The messages keep the recorded stamps: the node's pings are timed by them, not by the wall clock.
"""
import argparse
import csv
import math
import time

import rospy
from nav_msgs.msg import Odometry


def quaternion(yaw, pitch, roll):
    """(x, y, z, w) of the rotation yaw about z, then pitch about y, then roll about x."""
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trajectory", help="CSV file (see above)")
    parser.add_argument("--rate", type=float, default=1.0, help="speed-up factor (> 0)")
    args = parser.parse_args(rospy.myargv()[1:])
    if not args.rate > 0:
        parser.error(f"--rate = {args.rate}: must be > 0")
    rospy.init_node("trajectory")
    pub = rospy.Publisher("odom", Odometry, queue_size=1000)
    with open(args.trajectory, newline="") as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    deadline = time.time() + 10.0
    while pub.get_num_connections() == 0 and time.time() < deadline and not rospy.is_shutdown():
        time.sleep(0.05)
    start_wall, start_stamp = time.time(), rows[0]["stamp_s"]
    for seq, r in enumerate(rows):
        wait = start_wall + (r["stamp_s"] - start_stamp) / args.rate - time.time()
        if wait > 0:
            time.sleep(wait)
        if rospy.is_shutdown():
            return
        m = Odometry()
        m.header.seq = seq
        m.header.stamp = rospy.Time.from_sec(r["stamp_s"])
        m.header.frame_id = "odom"
        m.child_frame_id = "base_link"
        m.pose.pose.position.x, m.pose.pose.position.y = r["x_m"], r["y_m"]
        m.pose.pose.position.z = r["z_m"]
        q = m.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion(r["yaw_rad"], r["pitch_rad"], r["roll_rad"])
        m.twist.twist.linear.x = r["speed_m_s"]
        pub.publish(m)
    rospy.loginfo("trajectory: %d poses published", len(rows))
    time.sleep(1.0)  # let the last messages leave


if __name__ == "__main__":
    main()
