#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

const char *hpfc_strerror(int status)
{
    switch (status) {
    case HPFC_OK: return "success";
    case HPFC_E_NOMEM: return "out of memory";
    case HPFC_E_ARG: return "invalid argument";
    case HPFC_E_IO: return "input/output error";
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

const char *hpfc_version_string(void)
{
    return HPFC_VERSION_STRING;
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

double lattice_to_user(int64_t v, int32_t exp10)
{
    return (double)v * pow(10.0, (double)exp10);
}

void diag_clear(hpfc_diag *diag)
{
    if (diag) {
        memset(diag, 0, sizeof *diag);
        diag->edge[0] = diag->edge[1] = -1;
    }
}
