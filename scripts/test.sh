#!/usr/bin/env bash
# Installs what is missing, builds with assertions on, and runs the whole
# test suite (GoogleTest through CTest).
# Usage: bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=build-test BUILD_TYPE=RelWithAsserts bash scripts/build.sh -DFQ_WARNINGS_AS_ERRORS=ON
echo "[framequake] running the test suite"
ctest --test-dir build-test --output-on-failure -j "${JOBS:-$(nproc)}" -LE validation
