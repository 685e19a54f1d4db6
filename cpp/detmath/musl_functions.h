/* The musl functions kiloloop uses, under the names kiloloop_libm gives them (musl_rename.h):
 * musl's portable C (its src/math: FreeBSD's msun for the trigonometric and hyperbolic functions,
 * Arm's optimized-routines for exp, exp2, log, log2 and pow), compiled with -ffp-contract=off and
 * without __FP_FAST_FMA, so a result depends only on IEEE-754 double arithmetic, never on the
 * CPU's FMA or SIMD units (cmake/detmath.cmake). */
#ifndef KILOLOOP_DETMATH_MUSL_FUNCTIONS_H
#define KILOLOOP_DETMATH_MUSL_FUNCTIONS_H

#ifdef __cplusplus
extern "C" {
#endif

double kiloloop_musl_sin(double x);
double kiloloop_musl_cos(double x);
void kiloloop_musl_sincos(double x, double* s, double* c);
double kiloloop_musl_tan(double x);
double kiloloop_musl_asin(double x);
double kiloloop_musl_acos(double x);
double kiloloop_musl_atan(double x);
double kiloloop_musl_atan2(double y, double x);
double kiloloop_musl_sinh(double x);
double kiloloop_musl_cosh(double x);
double kiloloop_musl_tanh(double x);
double kiloloop_musl_asinh(double x);
double kiloloop_musl_acosh(double x);
double kiloloop_musl_atanh(double x);
double kiloloop_musl_exp(double x);
double kiloloop_musl_exp2(double x);
double kiloloop_musl_expm1(double x);
double kiloloop_musl_log(double x);
double kiloloop_musl_log2(double x);
double kiloloop_musl_log10(double x);
double kiloloop_musl_log1p(double x);
double kiloloop_musl_pow(double x, double y);
double kiloloop_musl_cbrt(double x);
double kiloloop_musl_hypot(double x, double y);

#ifdef __cplusplus
}
#endif

#endif
