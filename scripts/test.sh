#!/usr/bin/env bash
# Installs what is missing, builds with assertions on, and runs the whole
# test suite (GoogleTest through CTest).
# Usage: bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=build-test BUILD_TYPE=RelWithAsserts bash scripts/build.sh -DFQ_WARNINGS_AS_ERRORS=ON
echo "[framequake] running the test suite"
# Threads that wait passively: the determinism tests force OpenMP on tiny
# scenes, where libgomp's default spinning costs milliseconds per parallel
# region on a loaded 2-core machine.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
ctest --test-dir build-test --output-on-failure -j "${JOBS:-$(nproc)}" -LE validation
