#!/usr/bin/env bash
# The main job: install what is missing, build, and run seed 001's frames
# A, B and C side by side under the JMA Kobe record, with the comparison
# table and figure (framequake compare), and an animation of the three side
# by side (framequake render --compare).
# Usage: bash scripts/main.sh        (output in out/compare/)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=build BUILD_TYPE=Release bash scripts/build.sh
echo "[framequake] running frames A, B and C (cases/frame_*.yaml) side by side"
./build/apps/framequake compare cases/frame_A.yaml cases/frame_B.yaml cases/frame_C.yaml --out out/compare
echo "[framequake] rendering the three runs side by side (out/compare/abc.gif)"
./build/apps/framequake render --compare out/compare/frame_A out/compare/frame_B out/compare/frame_C \
  --to out/compare/abc.gif --every 2 --size 480x480
echo "[framequake] done: table out/compare/comparison.md, figure out/compare/first_storey_drift.png (every storey),"
echo "[framequake] animation out/compare/abc.gif; open out/compare/frame_A/case.pvd (and B, C) in ParaView"
