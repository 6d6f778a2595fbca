#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The live node's test (ctest ros_node): a ROS master on a free loopback port, the node
# sonarsynth_ros with parameters, `rosbag record` of its topics, the test driver (node_test.cpp);
# then the recorded bag read back with `sonarsynth info`. Everything started here is stopped on
# exit. Exit 77 (ctest: skipped) only if a ROS tool is missing.
# Usage: run_node_test.sh NODE TEST_DRIVER SONARSYNTH_CLI SCENE WORK_DIR
set -euo pipefail
node=$1 driver=$2 cli=$3 scene=$4 work=$5
for tool in rosmaster rosbag; do
  command -v "$tool" >/dev/null || { echo "run_node_test: $tool not found: skipped"; exit 77; }
done
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/../scripts/ros_master.sh"
trap stop_all EXIT
start_master "$work"

"$node" _scene:="$scene" _samples:=256 _sonar/frequency_khz:=410 _stats_every_s:=1 \
  >"$work/node.log" 2>&1 &
node_pid=$!
pids+=($node_pid)
# The recorder itself where Debian installs it (`rosbag record` runs it as a child, which a
# signal to the wrapper may outlive: then the bag is complete once its .active file is gone).
recorder=(rosbag record)
[ -x /usr/lib/rosbag/record ] && recorder=(/usr/lib/rosbag/record)
"${recorder[@]}" -O "$work/node.bag" __name:=node_test_record /sonarsynth/sidescan/port \
  /sonarsynth/sidescan/starboard /sonarsynth/fix /sonarsynth/imu /tf_static \
  >"$work/record.log" 2>&1 &
record=$!
pids+=($record)

status=0
SONARSYNTH_ROS_TEST_SCENE=$scene SONARSYNTH_ROS_TEST_OUT=$work \
  SONARSYNTH_ROS_TEST_RECORDER=/node_test_record "$driver" || status=$?
if ((status != 0)); then
  echo "--- node.log"; tail -30 "$work/node.log"
  exit "$status"
fi

# Stop the recorder (SIGINT: it closes the bag), then read the bag back.
stop "$record"
for _ in $(seq 100); do [ -f "$work/node.bag.active" ] || break; sleep 0.1; done
[ -f "$work/node.bag" ] || { echo "run_node_test: rosbag record wrote no bag"; cat "$work/record.log"; exit 1; }
"$cli" info --json "$work/node.bag" >"$work/info.json"
python3 - "$work/info.json" "$(cat "$work/pings.txt")" <<'PY'
import json, sys
info, expected = json.load(open(sys.argv[1])), int(sys.argv[2])
pings = info["pings"]
assert pings == expected, f"sonarsynth info: {pings} pings in the recorded bag, expected {expected}"
assert info["pings_with_valid_navigation"] == expected, info["pings_with_valid_navigation"]
assert info["pings_with_attitude"] == expected, info["pings_with_attitude"]
assert info["anomaly_count"] == 0, info["anomalies"]
print(f"run_node_test: the recorded bag holds {pings} pings (sonarsynth info)")
PY
stop "$node_pid"  # its summary: pings and latency
grep -h "in total" "$work/node.log" | tail -1 || true
