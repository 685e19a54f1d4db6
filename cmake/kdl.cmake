# KDL (orocos-kdl), built from Debian's source tarball with kiloloop's flags as the static library
# kiloloop_kdl: the version Debian bookworm ships (1.5.1), so the headers match the system's
# kdl_parser, which the C++ tests use as an oracle. Built from source, not Debian's binary:
# every target (x86-64, aarch64, Cortex-M7) compiles the same code with -ffp-contract=off and
# Eigen's explicit vectorization off (Debian's arm64 build holds fused multiply-adds), and its
# sin/cos/atan2/... calls bind to kiloloop_detmath like the core's (docs/firmware.md).
include("${CMAKE_CURRENT_LIST_DIR}/third_party.cmake")
kiloloop_fetch_source(KILOLOOP_KDL_SOURCE_DIR
  NAME orocos-kdl_1.5.1.orig.tar.gz
  SHA256 5acb90acd82b10971717aca6c17874390762ecdaa3a8e4db04984ea1d4a2af9b
  URLS "http://deb.debian.org/debian/pool/main/o/orocos-kdl/orocos-kdl_1.5.1.orig.tar.gz")
set(_kdl_src "${KILOLOOP_KDL_SOURCE_DIR}/orocos_kdl/src")

# newlib (a bare-metal target's C library, cmake/toolchain-cortex-m7.cmake) defines _L as a macro
# in <ctype.h> (a character class bit); KDL's LMA solver names a parameter _L. On that target the
# parameter is renamed in the extracted copy (build directory only; the same code otherwise).
if(CMAKE_SYSTEM_NAME STREQUAL Generic)
  foreach(_f chainiksolverpos_lma.hpp chainiksolverpos_lma.cpp)
    file(READ "${_kdl_src}/${_f}" _text)
    string(REGEX REPLACE "([^A-Za-z0-9_])_L([^A-Za-z0-9_])" "\\1L_weights\\2" _patched "${_text}")
    if(NOT _patched STREQUAL _text)
      file(WRITE "${_kdl_src}/${_f}" "${_patched}")
    endif()
  endforeach()
endif()

# Headers as the library installs them (<kdl/frames.hpp>, <kdl/utilities/...>) plus config.h as
# Debian's build configures it (KDL 1.5.1, HAVE_STL_CONTAINER_INCOMPLETE_TYPES).
set(KILOLOOP_KDL_INCLUDE_DIR "${CMAKE_BINARY_DIR}/third_party/kdl-include")
file(COPY "${_kdl_src}/" DESTINATION "${KILOLOOP_KDL_INCLUDE_DIR}/kdl"
     FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "*.inl")
set(KDL_VERSION_MAJOR 1)
set(KDL_VERSION_MINOR 5)
set(KDL_VERSION_PATCH 1)
set(KDL_VERSION 1.5.1)
set(HAVE_STL_CONTAINER_INCOMPLETE_TYPES ON)
configure_file("${_kdl_src}/config.h.in" "${KILOLOOP_KDL_INCLUDE_DIR}/kdl/config.h" @ONLY)

# The library sources the core, the bindings and the benches use (their headers, below) and what
# those call: 21 of KDL's 66 (all 66: 142 s CPU more per build directory, measured; a header of
# another solver needs its source added here, the link says which).
set(_kdl_sources chain chaindynparam chainfksolverpos_recursive
    chainidsolver_recursive_newton_euler chainiksolverpos_lma chainiksolverpos_nr_jl
    chainiksolvervel_pinv chainjnttojacsolver frames jntarray jntspaceinertiamatrix
    rigidbodyinertia rotationalinertia segment tree treeidsolver_recursive_newton_euler joint
    jacobian articulatedbodyinertia utilities/svd_HH)
list(TRANSFORM _kdl_sources PREPEND "${_kdl_src}/")
list(TRANSFORM _kdl_sources APPEND ".cpp")
list(APPEND _kdl_sources "${_kdl_src}/utilities/utility.cxx")
add_library(kiloloop_kdl STATIC ${_kdl_sources})
add_library(kiloloop::kdl ALIAS kiloloop_kdl)
set_target_properties(kiloloop_kdl PROPERTIES EXPORT_NAME kdl OUTPUT_NAME kiloloop_kdl)
target_include_directories(kiloloop_kdl SYSTEM PUBLIC
  $<BUILD_INTERFACE:${KILOLOOP_KDL_INCLUDE_DIR}>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# Its sources include their neighbours by relative path (config.h too: from the copied tree).
target_include_directories(kiloloop_kdl PRIVATE "${KILOLOOP_KDL_INCLUDE_DIR}/kdl")
target_link_libraries(kiloloop_kdl PUBLIC Eigen3::Eigen kiloloop_detmath)
# Eigen's explicit vectorization off for KDL, the core and everything that links them (a usage
# requirement, so every translation unit of a program agrees: Eigen's alignment and its template
# instances must be the same in all of them). Its SSE/AVX/NEON kernels sum and fuse in their own
# order (NEON fuses whatever -ffp-contract says): the scalar code gives the same bits on every
# target. GCC's own auto-vectorization stays: it never reorders floating-point operations.
target_compile_definitions(kiloloop_kdl PUBLIC EIGEN_DONT_VECTORIZE)
# Third-party code: its warnings are not kiloloop's to fix.
target_compile_options(kiloloop_kdl PRIVATE -w)
if(KILOLOOP_SANITIZE)
  # Instrumented like the core (ASan, and UBSan's other checks), but for UBSan's null check: KDL
  # 1.5.1's TreeIdSolver_RNE::rne_step takes a member through a null map node (stl_tree.h,
  # "member call on null pointer"), which the C++ tests reach through that solver, their oracle
  # (ChainFolding.ChainTorquesEqualTheTreeWithOffChainJointsLocked). KDL's to fix, not kiloloop's;
  # the core never calls that solver.
  target_compile_options(kiloloop_kdl PRIVATE -fno-sanitize=null)
endif()
