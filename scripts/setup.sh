#!/usr/bin/env bash
# Installs what the demo and the tests need, only what is missing (idempotent):
# Debian packages (ROS's interface parser, iproute2 for the private network namespace,
# nftables for the lossy-link tests, DejaVu fonts for motion_plot),
# Python packages (cyclonedds: an independent DDS peer; ruckig: trajectory oracle; pyyaml;
# mcap-ros2-support: the MCAP/ros2msg reader that checks our message definitions).
# The test command also builds the ROS 2 Jazzy venv of the rclpy suite (scripts/ros-venv.sh).
set -euo pipefail
SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"

need_apt=()
/usr/bin/python3 -c "import rosidl_adapter.parser" 2>/dev/null || need_apt+=(python3-rosidl)
command -v ip >/dev/null || need_apt+=(iproute2)
command -v unshare >/dev/null || need_apt+=(util-linux)
command -v nft >/dev/null || need_apt+=(nftables)   # lossy-link tests inside the namespace
# motion_plot writes its figures' text with DejaVu Sans.
[ -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] || need_apt+=(fonts-dejavu-core)
if [ ${#need_apt[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${need_apt[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}" >/dev/null
fi

PY=${PYTHON:-python3}
need_pip=()
$PY -c "import cyclonedds" 2>/dev/null || need_pip+=("cyclonedds==11.0.1")
$PY -c "import ruckig" 2>/dev/null || need_pip+=(ruckig)
$PY -c "import yaml" 2>/dev/null || need_pip+=(pyyaml)
$PY -c "import mcap_ros2._dynamic" 2>/dev/null || need_pip+=("mcap-ros2-support==0.6.0")
if [ ${#need_pip[@]} -gt 0 ]; then
  echo "setup: installing Python packages: ${need_pip[*]}"
  $PY -m pip install -q "${need_pip[@]}"
fi

command -v cargo >/dev/null || { echo "setup: cargo (Rust toolchain) is required" >&2; exit 1; }
