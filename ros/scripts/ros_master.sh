# SPDX-License-Identifier: MIT
# Sourced by ros/tests/run_node_test.sh and ros/bench/run_benchmark.sh: a ROS master of their own
# on a free loopback port, and the stopping of every process they start (listed in `pids`).

pids=()

# stop PID: SIGINT (a ROS node's clean shutdown), SIGTERM after 3 s, SIGKILL after 5 s.
stop() {
  local i
  kill -INT "$1" 2>/dev/null || return 0
  for i in $(seq 50); do
    kill -0 "$1" 2>/dev/null || return 0
    ((i == 30)) && kill -TERM "$1" 2>/dev/null
    sleep 0.1
  done
  kill -KILL "$1" 2>/dev/null || true
}

# Stops every process of `pids`, the last started first.
stop_all() {
  local i
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do stop "${pids[i]}"; done
}

# start_master WORK_DIR: rosmaster on a port the kernel picks, ROS_MASTER_URI and the ROS
# directories exported (logs under WORK_DIR), back when the master answers.
start_master() {
  local port
  port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOME=$1/ros_home
  export ROS_LOG_DIR=$1/log
  rosmaster --core -p "$port" -w 2 >"$1/master.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 100); do
    python3 -c "import xmlrpc.client as x; x.ServerProxy('$ROS_MASTER_URI').getPid('/t')" \
      >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  echo "start_master: rosmaster did not answer on $ROS_MASTER_URI" >&2
  return 1
}
