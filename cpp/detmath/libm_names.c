/* The C library's names for the transcendental functions, defined by SLEEF's (sleef_functions.h).
 *
 * Linked into a program (the Python module, a firmware binary) ahead of libm, these definitions
 * take every call of sin, cos, atan2, exp, ... in kiloloop's code, in KDL's and in the Eigen and
 * libstdc++ templates compiled into them: one implementation on every CPU and target, whatever
 * glibc would pick at run time (its FMA/AVX2 code paths) or another libc computes.
 * Hidden: inside a shared object (the Python module) they bind only that object's own calls;
 * MuJoCo, numpy and the interpreter keep the system's libm.
 *
 * sincos: GCC merges sin(x) and cos(x) of one argument into one sincos call (where the libc has
 * one; elsewhere it may keep the two calls): the bits must be the same merged or not, on any
 * target.
 * sqrt, fabs, floor, round, fmin, fmax, fmod, ...: exact by IEEE-754 and C, left to the C library.
 * Compiled with -fno-builtin: nothing here is turned back into a call of a C library name. */
#include "sleef_functions.h"

#define KILOLOOP_LIBM __attribute__((visibility("hidden")))

/* sincos computes sin and cos separately: the same bits whether the compiler merged the pair or
 * not. (SLEEF's sincos_u10 would cost one call for both, but its bits differ from sin_u10's and
 * cos_u10's; taking it for all three: bench/RESULTS.md, 2026-11-27.) */
KILOLOOP_LIBM double sin(double x) { return Sleef_sin_u10(x); }
KILOLOOP_LIBM double cos(double x) { return Sleef_cos_u10(x); }
KILOLOOP_LIBM void sincos(double x, double* s, double* c) {
  *s = Sleef_sin_u10(x);
  *c = Sleef_cos_u10(x);
}
KILOLOOP_LIBM double tan(double x) { return Sleef_tan_u10(x); }
KILOLOOP_LIBM double asin(double x) { return Sleef_asin_u10(x); }
KILOLOOP_LIBM double acos(double x) { return Sleef_acos_u10(x); }
KILOLOOP_LIBM double atan(double x) { return Sleef_atan_u10(x); }
KILOLOOP_LIBM double atan2(double y, double x) { return Sleef_atan2_u10(y, x); }
KILOLOOP_LIBM double sinh(double x) { return Sleef_sinh_u10(x); }
KILOLOOP_LIBM double cosh(double x) { return Sleef_cosh_u10(x); }
KILOLOOP_LIBM double tanh(double x) { return Sleef_tanh_u10(x); }
KILOLOOP_LIBM double asinh(double x) { return Sleef_asinh_u10(x); }
KILOLOOP_LIBM double acosh(double x) { return Sleef_acosh_u10(x); }
KILOLOOP_LIBM double atanh(double x) { return Sleef_atanh_u10(x); }
KILOLOOP_LIBM double exp(double x) { return Sleef_exp_u10(x); }
KILOLOOP_LIBM double exp2(double x) { return Sleef_exp2_u10(x); }
KILOLOOP_LIBM double expm1(double x) { return Sleef_expm1_u10(x); }
KILOLOOP_LIBM double log(double x) { return Sleef_log_u10(x); }
KILOLOOP_LIBM double log2(double x) { return Sleef_log2_u10(x); }
KILOLOOP_LIBM double log10(double x) { return Sleef_log10_u10(x); }
KILOLOOP_LIBM double log1p(double x) { return Sleef_log1p_u10(x); }
KILOLOOP_LIBM double pow(double x, double y) { return Sleef_pow_u10(x, y); }
KILOLOOP_LIBM double cbrt(double x) { return Sleef_cbrt_u10(x); }
KILOLOOP_LIBM double hypot(double x, double y) { return Sleef_hypot_u05(x, y); }
