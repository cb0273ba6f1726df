/* diag.h: the diagnostics every part of the library fills (hpfc_diag, its
 * message and culprit point) and the exact decimal form of lattice values
 * for messages (errors.c). Internal to the library (and its tests and
 * fuzzers). */
#ifndef HPFC_DIAG_H
#define HPFC_DIAG_H

#include <stdarg.h>

#include "hpfc.h"

/* Resets diag (if non-NULL) to 'no culprit'. */
void diag_clear(hpfc_diag *diag);

/* Fills diag's status and message (if non-NULL) and returns status. */
int diag_set(hpfc_diag *diag, int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Fills diag's point (if diag is non-NULL) for a message about lattice
 * point (x, y): user coordinates, x * 10^exp10. */
void diag_point(hpfc_diag *diag, double x, double y, int32_t exp10);

/* Writes lattice value v at scale 10^-frac_digits as an exact decimal
 * ("-1.25", "4", "3000"), for messages; frac_digits beyond 30 (a .pfc
 * file about to fail with HPFC_E_LIMIT) as "<digits>e-<d>". Returns buf. */
const char *lattice_to_text(int64_t v, int64_t frac_digits, char buf[64]);

#endif
