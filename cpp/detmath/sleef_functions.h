/* The SLEEF functions kiloloop uses: scalar, double precision, the 1-ulp variants (u10; hypot's
 * is u05), compiled from SLEEF's portable C source (src/libm/sleefdp.c) with -ffp-contract=off,
 * so a result depends only on IEEE-754 double arithmetic, never on the CPU's FMA or SIMD units.
 * Declared here rather than through SLEEF's generated sleef.h (its build runs helper programs). */
#ifndef KILOLOOP_DETMATH_SLEEF_FUNCTIONS_H
#define KILOLOOP_DETMATH_SLEEF_FUNCTIONS_H

#ifdef __cplusplus
extern "C" {
#endif

/* SLEEF's pair of doubles (its misc.h): sincos returns sin in x, cos in y. */
typedef struct {
  double x, y;
} Sleef_double2;

Sleef_double2 Sleef_sincos_u10(double x);
double Sleef_sin_u10(double x);
double Sleef_cos_u10(double x);
double Sleef_tan_u10(double x);
double Sleef_asin_u10(double x);
double Sleef_acos_u10(double x);
double Sleef_atan_u10(double x);
double Sleef_atan2_u10(double y, double x);
double Sleef_sinh_u10(double x);
double Sleef_cosh_u10(double x);
double Sleef_tanh_u10(double x);
double Sleef_asinh_u10(double x);
double Sleef_acosh_u10(double x);
double Sleef_atanh_u10(double x);
double Sleef_exp_u10(double x);
double Sleef_exp2_u10(double x);
double Sleef_expm1_u10(double x);
double Sleef_log_u10(double x);
double Sleef_log2_u10(double x);
double Sleef_log10_u10(double x);
double Sleef_log1p_u10(double x);
double Sleef_pow_u10(double x, double y);
double Sleef_cbrt_u10(double x);
double Sleef_hypot_u05(double x, double y);

#ifdef __cplusplus
}
#endif

#endif
