/*
 * verify_report.h: the message of a --verify report (hpfc_geometry_verify,
 * hpfc_labels_verify), in one place: the first disagreement, written as
 * one formatted line into the report's fixed-size message.
 */
#ifndef HPFC_VERIFY_REPORT_H
#define HPFC_VERIFY_REPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include "hpfc.h"

static inline int verify_message(char *message, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Writes the message (cut to size) and returns HPFC_E_CORRUPT. */
static inline int verify_message(char *message, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, size, fmt, ap);
    va_end(ap);
    return HPFC_E_CORRUPT;
}

#endif
