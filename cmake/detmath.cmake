# Deterministic math: every transcendental function the real-time code calls, from one
# implementation whose result depends only on IEEE-754 double arithmetic (docs/firmware.md).
#   kiloloop_sleef    SLEEF's scalar double-precision functions (Sleef_sin_u10, ...), compiled from
#                     its portable C source with kiloloop's flags (-O2 -ffp-contract=off): no FMA,
#                     no SIMD, no run-time CPU dispatch; the same code for every target
#   kiloloop_detmath  the C library's names (sin, cos, sincos, atan2, exp, ...) defined by those
#                     (cpp/detmath/libm_names.c, hidden): linked ahead of libm, they take the calls
# SLEEF 3.9.0 from Debian's source package (bookworm's 3.5.1 is no longer in the archive's pool;
# sleefdp.c is the same algorithm family, and 3.9.0's rename.h is not generated at build time).
include("${CMAKE_CURRENT_LIST_DIR}/third_party.cmake")
kiloloop_fetch_source(KILOLOOP_SLEEF_SOURCE_DIR
  NAME sleef_3.9.0.orig.tar.gz
  SHA256 b2a1acd3f1860299848b4e24238a4609fbb85761a1a85bac5573347b90d0440b
  URLS "http://deb.debian.org/debian/pool/main/s/sleef/sleef_3.9.0.orig.tar.gz")

add_library(kiloloop_sleef STATIC "${KILOLOOP_SLEEF_SOURCE_DIR}/src/libm/sleefdp.c"
            "${KILOLOOP_SLEEF_SOURCE_DIR}/src/libm/rempitab.c")
add_library(kiloloop::sleef ALIAS kiloloop_sleef)
set_target_properties(kiloloop_sleef PROPERTIES EXPORT_NAME sleef OUTPUT_NAME kiloloop_sleef
                      UNITY_BUILD OFF C_VISIBILITY_PRESET hidden)
target_include_directories(kiloloop_sleef PRIVATE "${KILOLOOP_SLEEF_SOURCE_DIR}/src/common"
                           "${KILOLOOP_SLEEF_SOURCE_DIR}/src/libm")
# DORENAME: the Sleef_*_u10 names (src/libm/rename.h). ENABLE_BUILTIN_MATH: its one libm call,
# sqrt, as the compiler's (an IEEE-754 exact operation; the sqrt instruction on every target).
# -fno-math-errno: that sqrt needs no C library call for errno either.
target_compile_definitions(kiloloop_sleef PRIVATE DORENAME ENABLE_BUILTIN_MATH)
target_compile_options(kiloloop_sleef PRIVATE -ffp-contract=off -fno-math-errno -w)
if(KILOLOOP_SANITIZE)
  # Scalar arithmetic and one constant table, third party: not instrumented (its integer tricks on
  # extreme arguments are SLEEF's to answer for; the fuzz targets feed it NaN, Inf and 1e308).
  target_compile_options(kiloloop_sleef PRIVATE -fno-sanitize=all)
endif()

add_library(kiloloop_detmath STATIC "${CMAKE_CURRENT_SOURCE_DIR}/cpp/detmath/libm_names.c")
add_library(kiloloop::detmath ALIAS kiloloop_detmath)
set_target_properties(kiloloop_detmath PROPERTIES EXPORT_NAME detmath OUTPUT_NAME kiloloop_detmath
                      UNITY_BUILD OFF)
target_compile_options(kiloloop_detmath PRIVATE -ffp-contract=off -fno-builtin)
target_link_libraries(kiloloop_detmath PUBLIC kiloloop_sleef)
