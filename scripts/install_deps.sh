#!/usr/bin/env bash
# Installs the Debian 12 packages framequake needs, only those missing.
# Idempotent: a second run installs nothing and says so.
set -euo pipefail

packages=(
  build-essential cmake
  libeigen3-dev libvtk9-dev libgsl-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  python3-vtk9 python3-matplotlib python3-numpy python3-pil
  xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[framequake] all required Debian packages are installed"
  exit 0
fi

echo "[framequake] installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "[framequake] error: not root and no sudo; install these packages first: ${missing[*]}" >&2
    exit 1
  fi
fi
# A fresh machine often runs apt itself at boot (unattended-upgrades,
# apt-daily), or another installer holds dpkg's lock: wait for it (up to
# 10 minutes, apt's DPkg::Lock::Timeout) instead of failing at once with
# "Could not get lock".
lock_wait=(-o DPkg::Lock::Timeout=600)
$SUDO apt-get "${lock_wait[@]}" update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get "${lock_wait[@]}" install -y --no-install-recommends "${missing[@]}"
