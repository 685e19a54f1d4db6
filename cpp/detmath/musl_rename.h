/* Force-included (-include) into every musl source kiloloop_libm compiles (cmake/detmath.cmake):
 * musl's public names become kiloloop_musl_<name>, so the library defines no C library name and
 * a program can hold musl's functions beside its libc's (the bench compares the two). The C
 * library's names are bound to these by cpp/detmath/libm_names.c. musl's internal functions
 * (__sin, __rem_pio2, __math_oflow, the tables) keep their names: reserved, and hidden.
 * Keep in step with musl_functions.h. */
#ifndef KILOLOOP_DETMATH_MUSL_RENAME_H
#define KILOLOOP_DETMATH_MUSL_RENAME_H

#define sin kiloloop_musl_sin
#define cos kiloloop_musl_cos
#define sincos kiloloop_musl_sincos
#define tan kiloloop_musl_tan
#define asin kiloloop_musl_asin
#define acos kiloloop_musl_acos
#define atan kiloloop_musl_atan
#define atan2 kiloloop_musl_atan2
#define sinh kiloloop_musl_sinh
#define cosh kiloloop_musl_cosh
#define tanh kiloloop_musl_tanh
#define asinh kiloloop_musl_asinh
#define acosh kiloloop_musl_acosh
#define atanh kiloloop_musl_atanh
#define exp kiloloop_musl_exp
#define exp2 kiloloop_musl_exp2
#define expm1 kiloloop_musl_expm1
#define log kiloloop_musl_log
#define log2 kiloloop_musl_log2
#define log10 kiloloop_musl_log10
#define log1p kiloloop_musl_log1p
#define pow kiloloop_musl_pow
#define cbrt kiloloop_musl_cbrt
#define hypot kiloloop_musl_hypot
/* exact by IEEE-754, called by the functions above (__rem_pio2_large) */
#define scalbn kiloloop_musl_scalbn
#define floor kiloloop_musl_floor

#endif
