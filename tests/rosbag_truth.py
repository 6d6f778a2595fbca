#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Independent reader of the truth topics of a sonarsynth ROS 1 bag (docs/robotics.md, "Truth
# topics"), run by tests/bag_truth_test.cpp: Debian's python3-rosbag decodes every message with a
# class genpy generates from the definition embedded in its connection; the MD5 sum genpy computes
# from that definition must be the connection's md5sum. Prints one JSON object (NaN as null);
# exits 1 with a message on any inconsistency. Usage: python3 rosbag_truth.py FILE.bag
import json
import math
import sys

import genpy.dynamic
import rosbag


def fail(message):
    sys.stderr.write(f"rosbag_truth: {message}\n")
    sys.exit(1)


def floats(values):
    return [None if math.isnan(v) else v for v in values]


def main():
    if len(sys.argv) != 2:
        fail("usage: python3 rosbag_truth.py FILE.bag")
    out = {"types": {}, "counts": {}, "truth": []}
    with rosbag.Bag(sys.argv[1]) as bag:
        conns = {c.topic: c for c in bag._get_connections()}
        for topic in sorted(conns):
            c = conns[topic]
            out["types"][topic] = c.datatype
            generated = genpy.dynamic.generate_dynamic(c.datatype, c.msg_def)[c.datatype]
            if generated._md5sum != c.md5sum:
                fail(f"{topic}: genpy's MD5 of the definition {generated._md5sum} != "
                     f"the connection's {c.md5sum}")
        images, truth = {}, []
        for topic, msg, t in bag.read_messages():
            out["counts"][topic] = out["counts"].get(topic, 0) + 1
            if type(msg)._md5sum != conns[topic].md5sum:
                fail(f"{topic}: message class MD5 {type(msg)._md5sum}")
            if msg._type == "marine_acoustic_msgs/RawSonarImage":
                images[(topic, t.to_nsec())] = msg
            elif msg._type == "sonarsynth_msgs/SideScanTruth":
                truth.append((topic, msg, t))
    for topic, msg, t in truth:
        # Stamped as the side's RawSonarImage: time, seq and frame.
        image = images.get((topic[: -len("/truth")], t.to_nsec()))
        if image is None or msg.header.stamp != t or msg.header.seq != image.header.seq or \
                msg.header.frame_id != image.header.frame_id:
            fail(f"{topic} at {t.to_nsec()} ns: no RawSonarImage of the same stamp and frame")
        if msg.samples != image.samples_per_beam:
            fail(f"{topic}: {msg.samples} samples, the image {image.samples_per_beam}")
        out["truth"].append({"topic": topic, "t_ns": t.to_nsec(),
                             "frame_id": msg.header.frame_id, "samples": msg.samples,
                             # uint8[] reads as bytes
                             "sample_class": list(bytearray(msg.sample_class)),
                             "label": list(msg.label), "grazing_rad": floats(msg.grazing_rad),
                             "ground_range_m": floats(msg.ground_range_m)})
    # Per ping (time) port then starboard.
    out["truth"].sort(key=lambda m: (m["t_ns"], m["topic"].endswith("/starboard/truth")))
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
