#!/usr/bin/env bash
# Configures and builds framequake into BUILD_DIR (default: build) with
# BUILD_TYPE (default: Release). Extra arguments go to CMake.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
build_type=${BUILD_TYPE:-Release}
jobs=${JOBS:-$(nproc)}
echo "[framequake] configuring $build_dir ($build_type)"
mkdir -p "$build_dir"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" "$@" >"$build_dir/configure.log" 2>&1 || {
  cat "$build_dir/configure.log" >&2; exit 1; }
echo "[framequake] building with $jobs jobs"
cmake --build "$build_dir" -j "$jobs"
