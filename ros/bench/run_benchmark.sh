#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The live node's benchmark (ros_node_benchmark.cpp) against a master on a free loopback port;
# the node renders on one thread. Usage: ros/bench/run_benchmark.sh [BUILD_DIR] [SCENE] [args...]
# (args: ros_node_benchmark's; NODE_ARGS: more node parameters, e.g. "_waterfall/every:=1").
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build} scene=${2:-samples/paper_pipes.yaml}
shift $(( $# < 2 ? $# : 2 ))
work=$(mktemp -d)
source ros/scripts/ros_master.sh
trap 'stop_all; rm -rf "$work"' EXIT
start_master "$work"
"$build/ros/sonarsynth_ros" _scene:="$PWD/$scene" _queue_size:=5000 ${NODE_ARGS:-} >"$work/node.log" 2>&1 &
pids+=($!)
"$build/ros/ros_node_benchmark" "$scene" "$@"
