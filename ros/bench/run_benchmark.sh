#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The live node's benchmark (ros_node_benchmark.cpp) against a master on a free loopback port;
# the node renders on one thread. Usage: ros/bench/run_benchmark.sh [BUILD_DIR] [SCENE] [args...]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build} scene=${2:-samples/paper_pipes.yaml}
shift $(( $# < 2 ? $# : 2 ))
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  sleep 0.5
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOME=$work ROS_LOG_DIR=$work/log
rosmaster --core -p "$port" -w 2 >"$work/master.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  python3 -c "import xmlrpc.client as x; x.ServerProxy('$ROS_MASTER_URI').getPid('/t')" \
    >/dev/null 2>&1 && break
  sleep 0.1
done
"$build/ros/sonarsynth_ros" _scene:="$PWD/$scene" _queue_size:=5000 >"$work/node.log" 2>&1 &
pids+=($!)
"$build/ros/ros_node_benchmark" "$scene" "$@"
