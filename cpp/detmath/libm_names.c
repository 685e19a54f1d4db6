/* The C library's names for the transcendental functions, defined by musl's (musl_functions.h).
 *
 * Linked into a program (the Python module, a firmware binary) ahead of libm, these definitions
 * take every call of sin, cos, atan2, exp, ... in kiloloop's code, in KDL's and in the Eigen and
 * libstdc++ templates compiled into them: one implementation on every CPU and target, whatever
 * glibc would pick at run time (its FMA/AVX2 code paths) or another libc (newlib on a
 * microcontroller) computes.
 * Hidden: inside a shared object (the Python module) they bind only that object's own calls;
 * MuJoCo, numpy and the interpreter keep the system's libm.
 *
 * sincos: GCC merges sin(x) and cos(x) of one argument into one sincos call (where the libc has
 * one; elsewhere it may keep the two calls). musl's sincos runs the same argument reduction and
 * kernels as its sin and cos, so the bits are the same merged or not (libm_names_test.cpp).
 * sqrt, fabs, floor, round, fmin, fmax, fmod, remainder, ...: exact by IEEE-754 and C, left to
 * the C library (or the compiler's instruction).
 * Compiled with -fno-builtin: nothing here is turned back into a call of a C library name. */
#include "musl_functions.h"

#define KILOLOOP_LIBM __attribute__((visibility("hidden")))

KILOLOOP_LIBM double sin(double x) { return kiloloop_musl_sin(x); }
KILOLOOP_LIBM double cos(double x) { return kiloloop_musl_cos(x); }
KILOLOOP_LIBM void sincos(double x, double* s, double* c) { kiloloop_musl_sincos(x, s, c); }
KILOLOOP_LIBM double tan(double x) { return kiloloop_musl_tan(x); }
KILOLOOP_LIBM double asin(double x) { return kiloloop_musl_asin(x); }
KILOLOOP_LIBM double acos(double x) { return kiloloop_musl_acos(x); }
KILOLOOP_LIBM double atan(double x) { return kiloloop_musl_atan(x); }
KILOLOOP_LIBM double atan2(double y, double x) { return kiloloop_musl_atan2(y, x); }
KILOLOOP_LIBM double sinh(double x) { return kiloloop_musl_sinh(x); }
KILOLOOP_LIBM double cosh(double x) { return kiloloop_musl_cosh(x); }
KILOLOOP_LIBM double tanh(double x) { return kiloloop_musl_tanh(x); }
KILOLOOP_LIBM double asinh(double x) { return kiloloop_musl_asinh(x); }
KILOLOOP_LIBM double acosh(double x) { return kiloloop_musl_acosh(x); }
KILOLOOP_LIBM double atanh(double x) { return kiloloop_musl_atanh(x); }
KILOLOOP_LIBM double exp(double x) { return kiloloop_musl_exp(x); }
KILOLOOP_LIBM double exp2(double x) { return kiloloop_musl_exp2(x); }
KILOLOOP_LIBM double expm1(double x) { return kiloloop_musl_expm1(x); }
KILOLOOP_LIBM double log(double x) { return kiloloop_musl_log(x); }
KILOLOOP_LIBM double log2(double x) { return kiloloop_musl_log2(x); }
KILOLOOP_LIBM double log10(double x) { return kiloloop_musl_log10(x); }
KILOLOOP_LIBM double log1p(double x) { return kiloloop_musl_log1p(x); }
KILOLOOP_LIBM double pow(double x, double y) { return kiloloop_musl_pow(x, y); }
KILOLOOP_LIBM double cbrt(double x) { return kiloloop_musl_cbrt(x); }
KILOLOOP_LIBM double hypot(double x, double y) { return kiloloop_musl_hypot(x, y); }
