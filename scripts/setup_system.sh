#!/usr/bin/env bash
# Installs the Debian packages the C++ core builds against (and video rendering needs), when any
# is missing.
# As root: apt-get installs them. Otherwise: prints the exact command and fails.
set -euo pipefail
# libosmesa6: CPU OpenGL for `--video` (MuJoCo offscreen rendering with MUJOCO_GL=osmesa).
# KDL and musl's math are not among them: CMake builds both from Debian's source tarballs,
# fetched at configure time (cmake/third_party.cmake). libkdl-parser-dev (the C++ tests' oracle)
# brings Debian's own KDL with it.
# g++-aarch64-linux-gnu, qemu-user: `kiloloop pil ROBOT --target aarch64` (cross compiler and
# user-mode emulator; measured here: 16 s to install, about 300 MB).
packages=(libeigen3-dev liburdfdom-dev libkdl-parser-dev libgtest-dev g++ libosmesa6
          g++-aarch64-linux-gnu qemu-user)
# gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib, qemu-system-arm: `kiloloop pil ROBOT
# --target cortex-m7` (bare-metal compiler, newlib's C++ library, the system emulator with the
# MPS2-AN500 machine); `make test` runs one family there. Measured here: 64 s to install and
# 2.5 GB (2,547 MB by apt; most of it newlib and libstdc++ built for every Arm multilib).
packages+=(gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
cmd="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "kiloloop needs Debian packages: ${missing[*]}" >&2
  echo "run as root:  $cmd" >&2
  exit 1
fi
echo "installing Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}"
