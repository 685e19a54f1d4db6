# Cross-compiling for a Cortex-M7 with a double-precision FPU (the STM32H7 class of flight
# controllers), bare metal, with Debian's arm-none-eabi-gcc and newlib
# (gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib: scripts/setup_system.sh):
#   cmake -S . -B build/cortex-m7 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-cortex-m7.cmake
# `kiloloop pil ROBOT --target cortex-m7` builds the firmware core and the firmware with it and
# runs them on QEMU's MPS2-AN500 machine (a Cortex-M7), the log read through semihosting
# (examples/firmware/cortex_m7/).
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR cortex-m7)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
# No OS to run a test executable on: CMake's compiler checks link a static library instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# The core: Cortex-M7, Thumb-2, the FPv5 double-precision FPU (16 double registers), hard-float
# calling convention (newlib's thumb/v7e-m+dp/hard multilib, chosen at link by the same flags).
# -ffp-contract=off as on every target: the FPU has VFMA.F64, and a fused multiply-add rounds
# once where x86-64's SIL rounds twice.
# As compile and link options, not CMAKE_<LANG>_FLAGS_INIT: a build that sets CMAKE_CXX_FLAGS
# (build.py's CORE_OPTIONS empties it) would drop those, and link hard-float code to soft-float.
set(_kl_m7_cpu -mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard)
add_compile_options(${_kl_m7_cpu} -ffp-contract=off
                    # each function and object in its own section: --gc-sections keeps only
                    # what the firmware calls
                    -ffunction-sections -fdata-sections)
add_link_options(${_kl_m7_cpu} -Wl,--gc-sections)

# Programs (cmake, python) from the host; libraries and headers of the target only, except Eigen:
# header-only and the same on every target, the host's /usr/include/eigen3 and its CMake package
# (/usr/share/eigen3/cmake) serve the cross build too.
set(CMAKE_FIND_ROOT_PATH /usr/lib/arm-none-eabi)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
