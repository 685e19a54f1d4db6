# Cross-compiling for a Cortex-A (aarch64) Linux computer, the legged robot's or a drone's
# companion computer, with Debian's g++-aarch64-linux-gnu (scripts/setup_system.sh):
#   cmake -S . -B build/aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64-linux-gnu.cmake
# `kiloloop pil ROBOT --target aarch64` builds the firmware core and the firmware with it and
# runs them under qemu-aarch64 (user mode).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
# Eigen is header-only and the same on every target: the host's /usr/include/eigen3 and its
# CMake package serve the cross build too.
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# Static executables (glibc linked in): they run under qemu-aarch64 without a sysroot, and at
# fixed addresses (no PIE), which the instruction counter's step markers need.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
