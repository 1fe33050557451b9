#!/usr/bin/env bash
# The main job: install what is missing, build, and run the demonstration.
# Usage: bash scripts/main.sh        (output in out/)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=build BUILD_TYPE=Release bash scripts/build.sh
echo "[framequake] running the main job"
./build/apps/framequake run cases/demo_falling_block.yaml --out out/demo_falling_block
echo "[framequake] done: open out/demo_falling_block/case.pvd in ParaView"
