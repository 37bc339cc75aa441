#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The README's quick start. On a fresh Debian bookworm machine (as root it installs what is missing):
#   bash tools/quickstart.sh demo   -> builds (Release), simulates a race on the bundled RATM ellipse track
#                                      (realistic profile) and localises it with the dual pose graph (the main job)
#   bash tools/quickstart.sh test   -> builds (Release) and runs the whole test suite
# Build folder: ./build (override with BUILD_DIR=...). Extra CMake flags: CMAKE_ARGS="...".
set -euo pipefail
mode=${1:-}
case "$mode" in demo|test) ;; *) echo "usage: bash tools/quickstart.sh demo|test" >&2; exit 2;; esac
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$root/build}

# libceres-dev: the benchmark's side-by-side peer (optional at build time); pybind11-dev, python3-dev and
# python3-numpy: the Python bindings and their tests (built with /usr/bin/python3); pkgconf: CI links a
# program through the installed dualgraph.pc (it came in only as a dependency before); nlohmann-json3-dev: the
# JSON writer's strings (header-only, build time only).
packages=(build-essential cmake libeigen3-dev libsuitesparse-dev libopenblas-dev libgtest-dev
          libbenchmark-dev libcli11-dev libyaml-cpp-dev libopencv-dev libceres-dev
          pybind11-dev python3-dev python3-numpy pkgconf nlohmann-json3-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "quickstart: missing packages: ${missing[*]} (run as root, or: sudo apt-get install ${missing[*]})" >&2
    exit 1
  fi
  echo "quickstart: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
# shellcheck disable=SC2086
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
if [ "$mode" = demo ]; then
  cmake --build "$build" -j "$jobs" --target dualgraph  # only what the demo runs (the tests take minutes more)
else
  cmake --build "$build" -j "$jobs"
fi

if [ "$mode" = demo ]; then
  # The main job: a simulated race on the bundled RATM ellipse track under a real flight's conditions (the
  # realistic profile: VIO in its own frame, 3 px corners, camera mount and clock errors, map error),
  # localised with the dual graph, the VIO's frame found from the detections.
  out="$build/demo"
  "$build/bin/dualgraph" simulate --track "$root/data/tracks/ratm_ellipse.yaml" --seed 1 --profile realistic \
    --out "$out/sequence"
  "$build/bin/dualgraph" run --sequence "$out/sequence" --out "$out/run"
  "$build/bin/dualgraph" report --run "$out/run" --out "$out/report.html"
else
  ctest --test-dir "$build" --output-on-failure -j "$jobs"
fi
