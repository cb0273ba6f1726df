/*
 * errors.c: what every caller of the library shares: the status codes'
 * texts and names, diagnostics, the version, and hpfc_free for what the
 * library hands over.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "diag.h"

const char *hpfc_strerror(int status)
{
    switch (status) {
    case HPFC_OK: return "success";
    case HPFC_E_NOMEM: return "out of memory";
    case HPFC_E_ARG: return "invalid argument";
    case HPFC_E_IO: return "input/output error";
    case HPFC_E_BUFFER_SMALL: return "the caller's buffer is too small";
    case HPFC_E_PFC_SYNTAX: return "syntax error in .pfc input";
    case HPFC_E_PFC_VERSION: return "missing or unsupported .pfc header";
    case HPFC_E_VERTEX_INDEX: return "vertex index out of range";
    case HPFC_E_DUPLICATE_POINT: return "two points coincide";
    case HPFC_E_ZERO_LENGTH: return "zero-length segment";
    case HPFC_E_LOOP_INTERIOR: return "loop edge with fewer than two interior points";
    case HPFC_E_ISOLATED_VERTEX: return "isolated vertex";
    case HPFC_E_NONPLANAR: return "edges cross or touch (non-planar input)";
    case HPFC_E_EXTENT: return "coordinates too large for the lattice";
    case HPFC_E_EMPTY: return "graph has no edge";
    case HPFC_E_TOO_MANY_PIXELS: return "flat grid exceeds the pixel limit";
    case HPFC_E_LIMIT: return "implementation limit exceeded";
    case HPFC_E_MAGIC: return "not an hpfc file (bad magic)";
    case HPFC_E_VERSION: return "unsupported hpfc format major version";
    case HPFC_E_INCOMPATIBLE: return "file uses an incompatible feature this reader does not know";
    case HPFC_E_TRUNCATED: return "file is truncated";
    case HPFC_E_CHECKSUM: return "checksum mismatch";
    case HPFC_E_HEADER: return "header field out of range";
    case HPFC_E_LEVEL_TABLE: return "inconsistent level table";
    case HPFC_E_SECTION: return "inconsistent section directory";
    case HPFC_E_CORRUPT: return "corrupt pixel data";
    case HPFC_E_NO_PIXEL: return "no such pixel";
    case HPFC_E_NO_SECTION: return "the file has no such section";
    default: return "unknown status code";
    }
}

const char *hpfc_status_name(int status)
{
#define NAME(code) \
    case code: return #code
    switch (status) {
    NAME(HPFC_OK);
    NAME(HPFC_E_NOMEM);
    NAME(HPFC_E_ARG);
    NAME(HPFC_E_IO);
    NAME(HPFC_E_BUFFER_SMALL);
    NAME(HPFC_E_PFC_SYNTAX);
    NAME(HPFC_E_PFC_VERSION);
    NAME(HPFC_E_VERTEX_INDEX);
    NAME(HPFC_E_DUPLICATE_POINT);
    NAME(HPFC_E_ZERO_LENGTH);
    NAME(HPFC_E_LOOP_INTERIOR);
    NAME(HPFC_E_ISOLATED_VERTEX);
    NAME(HPFC_E_NONPLANAR);
    NAME(HPFC_E_EXTENT);
    NAME(HPFC_E_EMPTY);
    NAME(HPFC_E_TOO_MANY_PIXELS);
    NAME(HPFC_E_LIMIT);
    NAME(HPFC_E_MAGIC);
    NAME(HPFC_E_VERSION);
    NAME(HPFC_E_INCOMPATIBLE);
    NAME(HPFC_E_TRUNCATED);
    NAME(HPFC_E_CHECKSUM);
    NAME(HPFC_E_HEADER);
    NAME(HPFC_E_LEVEL_TABLE);
    NAME(HPFC_E_SECTION);
    NAME(HPFC_E_CORRUPT);
    NAME(HPFC_E_NO_PIXEL);
    NAME(HPFC_E_NO_SECTION);
    default: return "HPFC_E_UNKNOWN";
    }
#undef NAME
}

const char *hpfc_version_string(void)
{
    return HPFC_VERSION_STRING;
}

unsigned hpfc_version_number(void)
{
    return HPFC_VERSION_NUMBER;
}

void hpfc_free(void *buffer)
{
    free(buffer);
}

int diag_set(hpfc_diag *diag, int status, const char *fmt, ...)
{
    if (diag) {
        va_list ap;
        diag->status = status;
        va_start(ap, fmt);
        vsnprintf(diag->message, sizeof diag->message, fmt, ap);
        va_end(ap);
    }
    return status;
}

/* 10^e as the double nearest it (a decimal literal), for |e| <= 30, the
 * units a graph may have; further out by repeated steps. Not pow(): the
 * reader links no libm. */
static double power_of_ten(int32_t e)
{
    static const double tens[31] = {
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
        1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22, 1e23, 1e24, 1e25, 1e26, 1e27, 1e28, 1e29,
        1e30};
    static const double tenths[31] = {
        1e-0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13,
        1e-14, 1e-15, 1e-16, 1e-17, 1e-18, 1e-19, 1e-20, 1e-21, 1e-22, 1e-23, 1e-24, 1e-25,
        1e-26, 1e-27, 1e-28, 1e-29, 1e-30};
    if (e >= 0 && e <= 30)
        return tens[e];
    if (e < 0 && e >= -30)
        return tenths[-e];
    double v = e > 0 ? tens[30] : tenths[30];
    for (int32_t k = 30; k < (e > 0 ? e : -e); k++)
        v = e > 0 ? v * 10 : v / 10;
    return v;
}

void diag_point(hpfc_diag *diag, double x, double y, int32_t exp10)
{
    if (diag) {
        diag->has_point = 1;
        double scale = power_of_ten(exp10);
        diag->x = x * scale;
        diag->y = y * scale;
    }
}

/* Fractional digits written out in full: a graph's unit goes down to
 * 10^-30 (hpfc_graph_set_unit_exp10), and 20 digits, a sign, "0." and 30
 * zeros fit in 64 bytes; likewise up to 10^30 (30 trailing zeros). */
#define LATTICE_TEXT_MAX_DIGITS 30

const char *lattice_to_text(int64_t v, int64_t d, char buf[64])
{
    char digits[32];
    uint64_t a = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    int n = snprintf(digits, sizeof digits, "%llu", (unsigned long long)a);
    char *o = buf;
    if (v < 0)
        *o++ = '-';
    if (a == 0 || d == 0) {
        strcpy(o, digits);
        return buf;
    }
    if (d > LATTICE_TEXT_MAX_DIGITS || d < -LATTICE_TEXT_MAX_DIGITS) {
        snprintf(o, 60, "%se%lld", digits, (long long)-d);
        return buf;
    }
    if (d < 0) { /* a unit coarser than 1: trailing zeros */
        strcpy(o, digits);
        o += n;
        for (int64_t k = 0; k < -d; k++)
            *o++ = '0';
        *o = '\0';
        return buf;
    }
    if (n <= d) {
        *o++ = '0';
        *o++ = '.';
        for (int64_t k = n; k < d; k++)
            *o++ = '0';
        strcpy(o, digits);
    } else {
        memcpy(o, digits, (size_t)(n - d));
        o += n - d;
        *o++ = '.';
        strcpy(o, digits + (n - d));
    }
    /* Drop the fraction's trailing zeros: "2.50" reads better as "2.5". */
    o = buf + strlen(buf) - 1;
    while (*o == '0')
        *o-- = '\0';
    if (*o == '.')
        *o = '\0';
    return buf;
}

void diag_clear(hpfc_diag *diag)
{
    if (diag) {
        memset(diag, 0, sizeof *diag);
        diag->edge[0] = diag->edge[1] = -1;
    }
}
