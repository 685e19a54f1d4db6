# Deterministic math: every transcendental function the real-time code calls, from one
# implementation whose result depends only on IEEE-754 double arithmetic (docs/firmware.md).
#   kiloloop_libm     musl's portable C math (src/math/*.c), compiled by kiloloop with its own
#                     flags under kiloloop_musl_* names (cpp/detmath/musl_rename.h): no FMA, no
#                     SIMD, no run-time CPU dispatch, the same C for every target (musl's
#                     per-architecture assembly is not used)
#   kiloloop_detmath  the C library's names (sin, cos, sincos, atan2, exp, ...) defined by those
#                     (cpp/detmath/libm_names.c, hidden): linked ahead of libm, they take the calls
# Why musl (bench/RESULTS.md, "Deterministic math"): its functions are written for exactly this,
# plain double arithmetic with the evaluation order fixed in the source (FLT_EVAL_METHOD 0 on
# every target here), below 1 ulp, and as fast as glibc's (its exp, log and pow are the same Arm
# optimized-routines code glibc runs). SLEEF's scalar 1-ulp functions, the first candidate, gave
# the same bits everywhere too but were 1.5-5.5x slower than glibc on 12 of 17 functions.
# musl 1.2.5 from Debian's source package (trixie's; bookworm's 1.2.3 has the same src/math).
include("${CMAKE_CURRENT_LIST_DIR}/third_party.cmake")
kiloloop_fetch_source(KILOLOOP_MUSL_SOURCE_DIR
  NAME musl_1.2.5.orig.tar.gz
  SHA256 a9a118bbe84d8764da0ea0d28b3ab3fae8477fc7e4085d90102b8596fc7c75e4
  URLS "http://deb.debian.org/debian/pool/main/m/musl/musl_1.2.5.orig.tar.gz")

# musl's headers for the target (its <math.h>, <float.h>, <stdint.h> and the internal libm.h),
# never the host libc's: the sources see the same declarations and macros on every target.
# bits/alltypes.h is generated the way musl's Makefile does (tools/mkalltypes.sed, in CMake).
string(TOLOWER "${CMAKE_SYSTEM_PROCESSOR}" _kl_cpu)
if(_kl_cpu MATCHES "^(x86_64|amd64)$")
  set(_kl_musl_arch x86_64)
elseif(_kl_cpu MATCHES "^(aarch64|arm64)$")
  set(_kl_musl_arch aarch64)
elseif(_kl_cpu MATCHES "^(arm|armv7|cortex-m)")
  set(_kl_musl_arch arm)
else()
  message(FATAL_ERROR "kiloloop: no deterministic math for processor '${CMAKE_SYSTEM_PROCESSOR}' "
                      "(x86_64, aarch64 and arm are supported: cmake/detmath.cmake)")
endif()
set(_kl_musl_gen "${CMAKE_BINARY_DIR}/third_party/musl-include-${_kl_musl_arch}")
set(_kl_alltypes "")
foreach(_in "${KILOLOOP_MUSL_SOURCE_DIR}/arch/${_kl_musl_arch}/bits/alltypes.h.in"
            "${KILOLOOP_MUSL_SOURCE_DIR}/include/alltypes.h.in")
  file(STRINGS "${_in}" _lines)
  foreach(_line IN LISTS _lines)
    if(_line MATCHES "^TYPEDEF (.*) ([^ ]*);$")
      string(APPEND _kl_alltypes "#if defined(__NEED_${CMAKE_MATCH_2}) && !defined(__DEFINED_${CMAKE_MATCH_2})\n"
             "typedef ${CMAKE_MATCH_1} ${CMAKE_MATCH_2};\n#define __DEFINED_${CMAKE_MATCH_2}\n#endif\n\n")
    elseif(_line MATCHES "^(STRUCT|UNION) *([^ ]*) (.*);$")
      string(TOLOWER "${CMAKE_MATCH_1}" _kind)
      string(APPEND _kl_alltypes "#if defined(__NEED_${_kind}_${CMAKE_MATCH_2}) && !defined(__DEFINED_${_kind}_${CMAKE_MATCH_2})\n"
             "${_kind} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3};\n#define __DEFINED_${_kind}_${CMAKE_MATCH_2}\n#endif\n\n")
    else()
      string(APPEND _kl_alltypes "${_line}\n")
    endif()
  endforeach()
endforeach()
file(CONFIGURE OUTPUT "${_kl_musl_gen}/bits/alltypes.h" CONTENT "${_kl_alltypes}" @ONLY)

# The functions of musl_rename.h and what they call (argument reduction, kernels, tables, the
# overflow/underflow helpers, scalbn and floor).
set(_kl_musl_math sin cos sincos tan __sin __cos __tan __rem_pio2 __rem_pio2_large asin acos atan
    atan2 sinh cosh tanh asinh acosh atanh __expo2 exp exp_data exp2 expm1 log log_data log2
    log2_data log10 log1p pow pow_data cbrt hypot __math_oflow __math_uflow __math_xflow
    __math_invalid __math_divzero scalbn floor)
list(TRANSFORM _kl_musl_math PREPEND "${KILOLOOP_MUSL_SOURCE_DIR}/src/math/")
list(TRANSFORM _kl_musl_math APPEND ".c")
add_library(kiloloop_libm STATIC ${_kl_musl_math})
add_library(kiloloop::libm ALIAS kiloloop_libm)
set_target_properties(kiloloop_libm PROPERTIES EXPORT_NAME libm OUTPUT_NAME kiloloop_libm
                      UNITY_BUILD OFF C_VISIBILITY_PRESET hidden)
target_include_directories(kiloloop_libm BEFORE PRIVATE
  "${KILOLOOP_MUSL_SOURCE_DIR}/arch/${_kl_musl_arch}" "${KILOLOOP_MUSL_SOURCE_DIR}/arch/generic"
  "${KILOLOOP_MUSL_SOURCE_DIR}/src/include" "${KILOLOOP_MUSL_SOURCE_DIR}/src/internal"
  "${_kl_musl_gen}" "${KILOLOOP_MUSL_SOURCE_DIR}/include")
# musl's own C flags (its Makefile: -std=c99 -nostdinc -fexcess-precision=standard
# -frounding-math), plus:
#   -ffp-contract=off   no fused multiply-add, whatever the target has (also kiloloop's default)
#   -U__FP_FAST_FMA     the Arm optimized-routines code (exp, log, pow) takes its exact-product
#                       path through __builtin_fma where the compiler says FMA is fast (aarch64,
#                       Cortex-M7): off, so every target runs the split-multiplication path
#   -fno-math-errno     sqrt and fabs as the instruction (exact), no C library call for errno
target_compile_options(kiloloop_libm PRIVATE -std=c99 -nostdinc -fexcess-precision=standard
                       -frounding-math -ffp-contract=off -U__FP_FAST_FMA -fno-math-errno
                       -include "${CMAKE_CURRENT_SOURCE_DIR}/cpp/detmath/musl_rename.h" -w)
if(KILOLOOP_SANITIZE)
  # Third-party scalar arithmetic and tables (its bit tricks on the union of a double and an
  # integer are musl's to answer for; the fuzz targets feed it NaN, Inf and 1e308): not
  # instrumented.
  target_compile_options(kiloloop_libm PRIVATE -fno-sanitize=all)
endif()

add_library(kiloloop_detmath STATIC "${CMAKE_CURRENT_SOURCE_DIR}/cpp/detmath/libm_names.c")
add_library(kiloloop::detmath ALIAS kiloloop_detmath)
set_target_properties(kiloloop_detmath PROPERTIES EXPORT_NAME detmath OUTPUT_NAME kiloloop_detmath
                      UNITY_BUILD OFF)
target_compile_options(kiloloop_detmath PRIVATE -ffp-contract=off -fno-builtin)
target_link_libraries(kiloloop_detmath PUBLIC kiloloop_libm)
