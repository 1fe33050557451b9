#!/usr/bin/env bash
# The main job: install what is missing, build, and run seed 001's frames
# A, B and C side by side under the JMA Kobe record, with the comparison
# table and figure (framequake compare).
# Usage: bash scripts/main.sh        (output in out/compare/)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=build BUILD_TYPE=Release bash scripts/build.sh
echo "[framequake] running frames A, B and C (cases/frame_*.yaml) side by side"
./build/apps/framequake compare cases/frame_A.yaml cases/frame_B.yaml cases/frame_C.yaml --out out/compare
echo "[framequake] done: table out/compare/comparison.md, figure out/compare/first_storey_drift.png;"
echo "[framequake] open out/compare/frame_A/case.pvd (and frame_B, frame_C) in ParaView"
