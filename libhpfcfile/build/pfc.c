/*
 * pfc.c: the plain-text .pfc reader (spec/pfc-format.md).
 *
 * Coordinates are exact decimals. A file whose finest coordinate has d
 * significant fractional digits lives on the lattice 10^-d, so every
 * coordinate becomes the integer value * 10^d. d is only known once the
 * whole file has been seen, hence two passes over the text:
 *
 *   pass 1  checks the encoding, the syntax and the record rules that need
 *           no lattice value (header, field counts, vertex indices, loops),
 *           and finds d;
 *   pass 2  reads the text again, scales every coordinate exactly, checks
 *           the extent and zero-length segments and builds the graph.
 *
 * Then the whole-graph checks run: duplicate vertices (one sort) and
 * isolated vertices. Both passes are linear in the length of the text and
 * keep nothing per token, so a huge file needs no more memory than its
 * graph. Numbers never go through strtod: a decimal is split into its
 * significant digits and a power of ten, with saturating counters, so
 * hostile input (10^400, 50000-digit numbers, e999999999) cannot overflow.
 *
 * The geometric rules (crossing edges) are hpfc_graph_validate()'s job.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "graph.h"

/* hpfc_graph_set_unit_exp10() accepts exponents down to -30. */
#define PFC_MAX_FRAC_DIGITS 30
/* 10^13 > HPFC_COORD_MAX, and scaling never divides: a decimal with more
 * significant digits than this can never fit the lattice. */
#define PFC_MANT_DIGITS 13
/* Digit counts and exponents saturate here (10^15), far beyond anything
 * that fits, so that sums of three of them cannot overflow an int64_t. */
#define PFC_SAT ((int64_t)1000000000000000)
/* Longest token text quoted in a message. */
#define PFC_QUOTE_MAX 32

typedef struct pfc_token {
    const char *p;
    size_t n;
} pfc_token;

/* An exact decimal: (neg ? -1 : 1) * mant * 10^exp, trailing zeros of the
 * significant digits moved into exp. Zero is mant = 0, exp = 0. */
typedef struct pfc_decimal {
    bool neg;
    bool huge;        /* more than PFC_MANT_DIGITS significant digits */
    int64_t mant;     /* the significant digits, when not huge */
    int64_t exp;
} pfc_decimal;

typedef struct pfc_reader {
    const char *text;
    size_t length;
    hpfc_diag *diag;
    /* line scanner */
    size_t pos;
    uint32_t line;
    /* fields of the current line (reused from line to line) */
    pfc_token *tok;
    size_t ntok, cap_tok;
    /* scaled interior points of the current edge (pass 2) */
    int64_t *xy;
    size_t cap_xy;
    /* pass 1 results */
    size_t nv, ne, np;  /* np: interior points (the chunks read it) */
    int64_t d;          /* largest number of significant fractional digits */
    uint32_t d_line;    /* first line where d is reached */
    hpfc_graph *g;      /* pass 2 result */
    /* a chunk of a larger text (hpfc_pfc_chunk_*): its edges may name
     * vertices of the chunks before, and unless it starts the text it has
     * no byte-order mark and no header */
    bool chunk, inner;
} pfc_reader;

/* ------------------------------------------------------------------------
 * Diagnostics
 * ------------------------------------------------------------------------ */

/* Reports a failure at `line`: "line N: <what>". */
static int fail(pfc_reader *r, int status, uint32_t line, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static int fail(pfc_reader *r, int status, uint32_t line, const char *fmt, ...)
{
    char what[sizeof r->diag->message];
    va_list ap;
    if (!r->diag)
        return status;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    r->diag->line = line;
    return diag_set(r->diag, status, "line %u: %s", (unsigned)line, what);
}

/* Copies a token for a message: at most PFC_QUOTE_MAX bytes, cut on a
 * UTF-8 boundary (tokens are valid UTF-8 by then), control bytes replaced
 * so that the message stays one line. */
static const char *quote(const pfc_token *t, char buf[PFC_QUOTE_MAX + 4])
{
    size_t n = t->n;
    if (n > PFC_QUOTE_MAX) {
        n = PFC_QUOTE_MAX;
        while (n > 0 && ((unsigned char)t->p[n] & 0xC0) == 0x80)
            n--;
    }
    for (size_t k = 0; k < n; k++) {
        unsigned char c = (unsigned char)t->p[k];
        buf[k] = (c < 0x20 || c == 0x7F) ? '?' : (char)c;
    }
    if (n < t->n) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    buf[n] = '\0';
    return buf;
}

/* The exponent of user coordinates at scale 10^-d, for the diag's point.
 * Beyond 10^-400 a double is 0 anyway; the clamp keeps the cast safe. */
static int32_t user_exp10(const pfc_reader *r)
{
    return r->d > 400 ? -400 : (int32_t)-r->d;
}

static void diag_edge(pfc_reader *r, size_t edge)
{
    if (r->diag)
        r->diag->edge[0] = (int64_t)edge;
}

/* ------------------------------------------------------------------------
 * Lines and fields
 * ------------------------------------------------------------------------ */

/* Moves to the next line and sets [*b, *e) to its content without the
 * "\n" or "\r\n" terminator. Returns false at the end of the text. */
static bool next_line(pfc_reader *r, const char **b, const char **e)
{
    if (r->pos >= r->length)
        return false;
    const char *start = r->text + r->pos;
    size_t rest = r->length - r->pos;
    const char *nl = memchr(start, '\n', rest);
    const char *end = nl ? nl : start + rest;
    r->pos += (size_t)(end - start) + (nl ? 1 : 0);
    if (end > start && end[-1] == '\r')
        end--;
    /* Line numbers saturate: diag->line is 32 bits, and a 4-billion-line
     * file still reads correctly; only its messages get vaguer. */
    if (r->line < UINT32_MAX)
        r->line++;
    *b = start;
    *e = end;
    return true;
}

/* Length of the UTF-8 sequence starting at p[0] (within n bytes), or 0 if
 * it is not a well-formed one (RFC 3629: no overlong forms, surrogates or
 * code points beyond U+10FFFF). */
static size_t utf8_sequence(const unsigned char *p, size_t n)
{
    unsigned char c = p[0];
    size_t len;
    unsigned char lo = 0x80, hi = 0xBF;   /* range of the second byte */
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        if (c == 0xE0)
            lo = 0xA0;
        else if (c == 0xED)
            hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        if (c == 0xF0)
            lo = 0x90;
        else if (c == 0xF4)
            hi = 0x8F;
    } else
        return 0;
    if (n < len || p[1] < lo || p[1] > hi)
        return 0;
    for (size_t k = 2; k < len; k++)
        if ((p[k] & 0xC0) != 0x80)
            return 0;
    return len;
}

/* Pass 1: the whole line, comment included, must be NUL-free UTF-8. */
static int check_encoding(pfc_reader *r, const char *b, const char *e)
{
    const unsigned char *p = (const unsigned char *)b;
    size_t n = (size_t)(e - b);
    for (size_t k = 0; k < n;) {
        if (p[k] == 0)
            return fail(r, HPFC_E_PFC_SYNTAX, r->line, "NUL byte at column %zu", k + 1);
        size_t len = utf8_sequence(p + k, n - k);
        if (!len)
            return fail(r, HPFC_E_PFC_SYNTAX, r->line,
                        "invalid UTF-8 (byte 0x%02X at column %zu)", p[k], k + 1);
        k += len;
    }
    return HPFC_OK;
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Splits the line, minus its comment, into r->tok[0 .. r->ntok). */
static int split_fields(pfc_reader *r, const char *b, const char *e)
{
    const char *hash = memchr(b, '#', (size_t)(e - b));
    if (hash)
        e = hash;
    r->ntok = 0;
    while (b < e) {
        while (b < e && is_blank(*b))
            b++;
        if (b == e)
            break;
        const char *start = b;
        while (b < e && !is_blank(*b))
            b++;
        if (r->ntok == r->cap_tok) {
            size_t cap = r->cap_tok ? 2 * r->cap_tok : 16;
            pfc_token *t = cap <= SIZE_MAX / sizeof *t
                               ? realloc(r->tok, cap * sizeof *t) : NULL;
            if (!t)
                return fail(r, HPFC_E_NOMEM, r->line, "out of memory");
            r->tok = t;
            r->cap_tok = cap;
        }
        r->tok[r->ntok].p = start;
        r->tok[r->ntok].n = (size_t)(b - start);
        r->ntok++;
    }
    return HPFC_OK;
}

static bool token_is(const pfc_token *t, const char *word)
{
    size_t n = strlen(word);
    return t->n == n && memcmp(t->p, word, n) == 0;
}

/* ------------------------------------------------------------------------
 * Numbers
 * ------------------------------------------------------------------------ */

static int64_t sat_add(int64_t a, int64_t b)
{
    return a > PFC_SAT - b ? PFC_SAT : a + b;   /* a, b >= 0 */
}

/* Consumes a run of digits into x. *sig counts the significant digits up to
 * the last non-zero one; *tz counts the zeros after it, which are held back
 * so that they end in the exponent rather than in the mantissa. Returns the
 * end of the run. */
static const char *scan_digits(const char *p, const char *end, pfc_decimal *x,
                               int64_t *sig, int64_t *tz)
{
    for (; p < end && *p >= '0' && *p <= '9'; p++) {
        int digit = *p - '0';
        if (digit == 0) {
            if (*sig)
                *tz = sat_add(*tz, 1);
            continue;
        }
        *sig = *sig ? sat_add(*sig, sat_add(*tz, 1)) : 1;
        if (*sig <= PFC_MANT_DIGITS) {
            for (int64_t k = 0; k < *tz; k++)   /* *tz < PFC_MANT_DIGITS */
                x->mant *= 10;
            x->mant = x->mant * 10 + digit;
        } else {
            x->huge = true;
        }
        *tz = 0;
    }
    return p;
}

/* Parses [+-]? digit+ ('.' digit+)? ([eE] [+-]? digit+)? exactly.
 * Returns false on any other text. */
static bool parse_decimal(const pfc_token *t, pfc_decimal *out)
{
    const char *p = t->p, *end = t->p + t->n;
    pfc_decimal x = {false, false, 0, 0};
    int64_t sig = 0, tz = 0, frac_digits = 0, e10 = 0;
    bool e_neg = false;

    if (p < end && (*p == '+' || *p == '-'))
        x.neg = *p++ == '-';
    const char *start = p;
    p = scan_digits(p, end, &x, &sig, &tz);
    if (p == start)
        return false;
    if (p < end && *p == '.') {
        start = ++p;
        p = scan_digits(p, end, &x, &sig, &tz);
        if (p == start)
            return false;
        frac_digits = (size_t)(p - start) < (size_t)PFC_SAT ? (int64_t)(p - start) : PFC_SAT;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < end && (*p == '+' || *p == '-'))
            e_neg = *p++ == '-';
        start = p;
        for (; p < end && *p >= '0' && *p <= '9'; p++)
            e10 = e10 >= PFC_SAT / 10 ? PFC_SAT : e10 * 10 + (*p - '0');
        if (p == start)
            return false;
    }
    if (p != end)
        return false;
    if (sig == 0) {
        x.neg = false;      /* -0 is 0 */
    } else {
        x.exp = (e_neg ? -e10 : e10) - frac_digits + tz;
    }
    *out = x;
    return true;
}

/* Number of significant fractional digits of x (0 for integers). */
static int64_t frac_digits_of(const pfc_decimal *x)
{
    return x->exp < 0 ? -x->exp : 0;
}

/* x * 10^d as a lattice value, or false if its magnitude exceeds
 * HPFC_COORD_MAX. d >= frac_digits_of(x), so this never divides. */
static bool scale_decimal(const pfc_decimal *x, int64_t d, int64_t *out)
{
    if (x->huge)
        return false;
    if (x->mant == 0) {
        *out = 0;
        return true;
    }
    int64_t shift = x->exp + d, v = x->mant;
    for (int64_t k = 0; k < shift; k++) {
        if (v > HPFC_COORD_MAX)   /* also bounds the loop: at most 13 turns */
            return false;
        v *= 10;
    }
    if (v > HPFC_COORD_MAX)
        return false;
    *out = x->neg ? -v : v;
    return true;
}

/* Parses a vertex index: digit+ (no sign, no fraction). Values beyond
 * 32 bits saturate: they are out of range anyway. */
static bool parse_index(const pfc_token *t, uint64_t *out)
{
    uint64_t v = 0;
    if (t->n == 0)
        return false;
    for (size_t k = 0; k < t->n; k++) {
        char c = t->p[k];
        if (c < '0' || c > '9')
            return false;
        v = v > UINT32_MAX ? v : v * 10 + (uint64_t)(c - '0');
    }
    *out = v;
    return true;
}

/* ------------------------------------------------------------------------
 * Pass 1: syntax and record rules
 * ------------------------------------------------------------------------ */

/* The first record must be `pfc 1`. */
static int check_header(pfc_reader *r)
{
    char q[PFC_QUOTE_MAX + 4];
    uint64_t version;
    if (!token_is(&r->tok[0], "pfc"))
        return fail(r, HPFC_E_PFC_VERSION, r->line,
                    "the first record must be the header 'pfc 1', not '%s'",
                    quote(&r->tok[0], q));
    if (r->ntok < 2)
        return fail(r, HPFC_E_PFC_SYNTAX, r->line, "header 'pfc' has no version number");
    if (!parse_index(&r->tok[1], &version))
        return fail(r, HPFC_E_PFC_SYNTAX, r->line, "bad version number '%s'",
                    quote(&r->tok[1], q));
    /* The version decides the rest of the syntax, so it is judged before
     * the field count: a future `pfc 2 ...` header is a version error. */
    if (version != 1)
        return fail(r, HPFC_E_PFC_VERSION, r->line,
                    "unsupported .pfc version '%s' (this reader knows version 1)",
                    quote(&r->tok[1], q));
    if (r->ntok > 2)
        return fail(r, HPFC_E_PFC_SYNTAX, r->line, "extra field after 'pfc 1'");
    return HPFC_OK;
}

/* Pass 1: checks a coordinate's syntax and updates d. */
static int note_coordinate(pfc_reader *r, const pfc_token *t)
{
    char q[PFC_QUOTE_MAX + 4];
    pfc_decimal x;
    if (!parse_decimal(t, &x))
        return fail(r, HPFC_E_PFC_SYNTAX, r->line, "bad number '%s'", quote(t, q));
    if (frac_digits_of(&x) > r->d) {
        r->d = frac_digits_of(&x);
        r->d_line = r->line;
    }
    return HPFC_OK;
}

static int check_vertex(pfc_reader *r)
{
    if (r->ntok != 3)
        return fail(r, HPFC_E_PFC_SYNTAX, r->line,
                    "vertex record needs 2 coordinates, found %zu", r->ntok - 1);
    int st = note_coordinate(r, &r->tok[1]);
    if (!st)
        st = note_coordinate(r, &r->tok[2]);
    if (!st)
        r->nv++;
    return st;
}

/* Checks that the edge's end `which` (1 or 2) names an earlier vertex. */
static int check_edge_end(pfc_reader *r, uint64_t index, int which)
{
    char q[PFC_QUOTE_MAX + 4];
    if (index < r->nv)
        return HPFC_OK;
    diag_edge(r, r->ne);
    if (r->nv == 1)
        return fail(r, HPFC_E_VERTEX_INDEX, r->line,
                    "edge names vertex %s but only 1 vertex is defined",
                    quote(&r->tok[which], q));
    return fail(r, HPFC_E_VERTEX_INDEX, r->line,
                "edge names vertex %s but only %zu vertices are defined",
                quote(&r->tok[which], q), r->nv);
}

static int check_edge(pfc_reader *r)
{
    char q[PFC_QUOTE_MAX + 4];
    uint64_t u = 0, v = 0;
    int st;
    if (r->ntok < 3)
        return fail(r, HPFC_E_PFC_SYNTAX, r->line,
                    "edge record needs 2 vertex indices, found %zu", r->ntok - 1);
    for (int k = 1; k <= 2; k++)
        if (!parse_index(&r->tok[k], k == 1 ? &u : &v))
            return fail(r, HPFC_E_PFC_SYNTAX, r->line,
                        "bad vertex index '%s' (expected digits only)",
                        quote(&r->tok[k], q));
    if ((r->ntok - 3) % 2)
        return fail(r, HPFC_E_PFC_SYNTAX, r->line,
                    "edge has an odd number (%zu) of interior coordinates", r->ntok - 3);
    for (size_t k = 3; k < r->ntok; k++)
        if ((st = note_coordinate(r, &r->tok[k])))
            return st;
    if (!r->chunk && ((st = check_edge_end(r, u, 1)) || (st = check_edge_end(r, v, 2))))
        return st; /* a chunk's fill checks its ends against the chunks before too */
    if (u == v && r->ntok - 3 < 4) {
        diag_edge(r, r->ne);
        return fail(r, HPFC_E_LOOP_INTERIOR, r->line,
                    "loop at vertex %llu has %zu interior point%s; it needs at least 2",
                    (unsigned long long)u, (r->ntok - 3) / 2, r->ntok == 5 ? "" : "s");
    }
    r->ne++;
    r->np += (r->ntok - 3) / 2;
    return HPFC_OK;
}

static int check_record(pfc_reader *r, bool *header_seen)
{
    char q[PFC_QUOTE_MAX + 4];
    const pfc_token *kw = &r->tok[0];
    if (!*header_seen) {
        *header_seen = true;
        return check_header(r);
    }
    if (token_is(kw, "v"))
        return check_vertex(r);
    if (token_is(kw, "e"))
        return check_edge(r);
    if (token_is(kw, "pfc"))
        return fail(r, HPFC_E_PFC_VERSION, r->line,
                    "'pfc' header repeated; it must be the first record only");
    return fail(r, HPFC_E_PFC_SYNTAX, r->line, "unknown record '%s'", quote(kw, q));
}

/* Offset of the first line: a UTF-8 byte-order mark is not a record, and
 * some editors add one unasked, so it is skipped. */
static size_t text_start(const pfc_reader *r)
{
    if (r->inner)
        return 0;
    return (r->length >= 3 && memcmp(r->text, "\xEF\xBB\xBF", 3) == 0) ? 3 : 0;
}

/* Line of the end of the text, for errors that have no better culprit. */
static uint32_t last_line(const pfc_reader *r)
{
    return r->line ? r->line : 1;
}

static int pass1(pfc_reader *r)
{
    const char *b, *e;
    bool header_seen = false;
    int st;
    r->pos = text_start(r);
    while (next_line(r, &b, &e)) {
        if ((st = check_encoding(r, b, e)) || (st = split_fields(r, b, e)))
            return st;
        if (r->ntok && (st = check_record(r, &header_seen)))
            return st;
    }
    if (!header_seen)
        return fail(r, HPFC_E_PFC_VERSION, last_line(r),
                    "end of input before the 'pfc 1' header");
    if (r->ne == 0)
        return fail(r, HPFC_E_EMPTY, last_line(r), "end of input, but no edge was defined");
    return HPFC_OK;
}

/* ------------------------------------------------------------------------
 * Pass 2: exact scaling and graph construction
 * ------------------------------------------------------------------------ */

/* Scales token t by 10^d into *out, or reports an extent error. */
static int scale_token(pfc_reader *r, const pfc_token *t, int64_t *out)
{
    char q[PFC_QUOTE_MAX + 4];
    pfc_decimal x;
    if (!parse_decimal(t, &x))   /* pass 1 accepted it; keep the check cheap */
        return fail(r, HPFC_E_PFC_SYNTAX, r->line, "bad number '%s'", quote(t, q));
    if (scale_decimal(&x, r->d, out))
        return HPFC_OK;
    if (r->d == 0)
        return fail(r, HPFC_E_EXTENT, r->line,
                    "coordinate %s exceeds 2^40 in magnitude", quote(t, q));
    return fail(r, HPFC_E_EXTENT, r->line,
                "coordinate %s exceeds 2^40 lattice units of 10^-%lld "
                "(line %u has %lld fractional digits)",
                quote(t, q), (long long)r->d, (unsigned)r->d_line, (long long)r->d);
}

/* Reports a failure of hpfc_graph_add_vertex/edge (memory or size). */
static int graph_failure(pfc_reader *r, int st)
{
    if (st == HPFC_E_NOMEM)
        return fail(r, st, r->line, "out of memory");
    return fail(r, st, r->line, "graph too large: %s", hpfc_strerror(st));
}

static int build_vertex(pfc_reader *r)
{
    int64_t x, y;
    int st;
    if ((st = scale_token(r, &r->tok[1], &x)) || (st = scale_token(r, &r->tok[2], &y)))
        return st;
    if ((st = hpfc_graph_add_vertex(r->g, x, y, NULL)))
        return graph_failure(r, st);
    graph_set_last_vertex_line(r->g, r->line);
    return HPFC_OK;
}

/* Point k of the edge being built: the end vertex u, the interior points,
 * then the end vertex v. */
static void edge_point(const pfc_reader *r, uint32_t u, uint32_t v, size_t n_interior,
                       size_t k, int64_t p[2])
{
    const int64_t *s = k == 0 ? r->g->vxy + 2 * (size_t)u
                     : k == n_interior + 1 ? r->g->vxy + 2 * (size_t)v
                     : r->xy + 2 * (k - 1);
    p[0] = s[0];
    p[1] = s[1];
}

/* Two consecutive points of a polyline must differ. */
static int check_zero_length(pfc_reader *r, uint32_t u, uint32_t v, size_t n_interior)
{
    char xs[64], ys[64];
    int64_t a[2], b[2];
    edge_point(r, u, v, n_interior, 0, a);
    for (size_t k = 1; k <= n_interior + 1; k++, a[0] = b[0], a[1] = b[1]) {
        edge_point(r, u, v, n_interior, k, b);
        if (a[0] != b[0] || a[1] != b[1])
            continue;
        diag_edge(r, r->g->ne);
        diag_point(r->diag, (double)a[0], (double)a[1], user_exp10(r));
        return fail(r, HPFC_E_ZERO_LENGTH, r->line,
                    "zero-length segment: edge points %zu and %zu are both (%s, %s)",
                    k - 1, k, lattice_to_text(a[0], r->d, xs), lattice_to_text(a[1], r->d, ys));
    }
    return HPFC_OK;
}

static int build_edge(pfc_reader *r)
{
    uint64_t u = 0, v = 0;
    size_t ncoord = r->ntok - 3;
    int st;
    parse_index(&r->tok[1], &u);   /* pass 1 checked syntax and range */
    parse_index(&r->tok[2], &v);
    if (ncoord > r->cap_xy) {
        int64_t *xy = ncoord <= SIZE_MAX / sizeof *xy ? realloc(r->xy, ncoord * sizeof *xy) : NULL;
        if (!xy)
            return fail(r, HPFC_E_NOMEM, r->line, "out of memory");
        r->xy = xy;
        r->cap_xy = ncoord;
    }
    for (size_t k = 0; k < ncoord; k++)
        if ((st = scale_token(r, &r->tok[3 + k], &r->xy[k])))
            return st;
    if ((st = check_zero_length(r, (uint32_t)u, (uint32_t)v, ncoord / 2)))
        return st;
    if ((st = hpfc_graph_add_edge(r->g, (uint32_t)u, (uint32_t)v, r->xy, ncoord / 2, NULL)))
        return graph_failure(r, st);
    graph_set_last_edge_line(r->g, r->line);
    return HPFC_OK;
}

static int pass2(pfc_reader *r)
{
    const char *b, *e;
    bool header_done = false;
    int st;
    r->pos = text_start(r);
    r->line = 0;
    while (next_line(r, &b, &e)) {
        if ((st = split_fields(r, b, e)))
            return st;
        if (!r->ntok)
            continue;
        if (!header_done)
            header_done = true;   /* the header, checked by pass 1 */
        else if ((st = token_is(&r->tok[0], "v") ? build_vertex(r) : build_edge(r)))
            return st;
    }
    return HPFC_OK;
}

/* ------------------------------------------------------------------------
 * Whole-graph checks
 * ------------------------------------------------------------------------ */

/* Duplicate vertices then isolated ones (graph_check.c), in the order of
 * spec/pfc-format.md §5; every vertex has its line, so the messages have
 * the "line N: " shape. */
static int check_graph(pfc_reader *r)
{
    int st = graph_check_duplicates(r->g, false, r->diag);
    if (!st)
        st = graph_check_isolated(r->g, r->diag);
    return st == HPFC_E_NOMEM ? fail(r, st, last_line(r), "out of memory") : st;
}

/* The unit exponent of the graph is -d; the graph cannot go finer. */
static int check_resolution(pfc_reader *r)
{
    if (r->d <= PFC_MAX_FRAC_DIGITS)
        return hpfc_graph_set_unit_exp10(r->g, (int32_t)-r->d);
    return fail(r, HPFC_E_LIMIT, r->d_line,
                "coordinate has %lld significant fractional digits; at most %d are supported",
                (long long)r->d, PFC_MAX_FRAC_DIGITS);
}

/* ------------------------------------------------------------------------
 * Entry points
 * ------------------------------------------------------------------------ */

int hpfc_pfc_parse(const char *text, size_t length, hpfc_graph **out, hpfc_diag *diag)
{
    pfc_reader r;
    int st;
    diag_clear(diag);
    if (out)
        *out = NULL;
    if (!out || (!text && length))
        return diag_set(diag, HPFC_E_ARG, "hpfc_pfc_parse: NULL argument");
    memset(&r, 0, sizeof r);
    r.text = text ? text : "";
    r.length = length;
    r.diag = diag;
    st = pass1(&r);
    if (!st && (st = hpfc_graph_create(&r.g)))
        st = fail(&r, st, last_line(&r), "out of memory");
    if (!st)
        st = pass2(&r);
    if (!st)
        st = check_resolution(&r);
    if (!st)
        st = check_graph(&r);
    free(r.tok);
    free(r.xy);
    if (st) {
        hpfc_graph_free(r.g);
        return st;
    }
    *out = r.g;
    return HPFC_OK;
}

/* Reads all of an open stream into a malloc'd buffer (works for pipes,
 * where the size is not known in advance). */
static int read_stream(FILE *f, char **buf, size_t *len)
{
    size_t cap = 1 << 16, n = 0;
    char *b = malloc(cap);
    if (!b)
        return HPFC_E_NOMEM;
    for (;;) {
        n += fread(b + n, 1, cap - n, f);
        if (n < cap)
            break;
        char *nb = cap <= SIZE_MAX / 2 ? realloc(b, cap * 2) : NULL;
        if (!nb) {
            free(b);
            return HPFC_E_NOMEM;
        }
        b = nb;
        cap *= 2;
    }
    if (ferror(f)) {
        free(b);
        return HPFC_E_IO;
    }
    *buf = b;
    *len = n;
    return HPFC_OK;
}

/* A regular file's text mapped read-only (*map set, for munmap): its pages
 * are the page cache's, which the kernel may drop and read again, so a
 * large map's text (read twice, by pass 1 and pass 2) does not sit in the
 * process's own memory beside the graph it becomes. NULL *map otherwise:
 * a pipe, an empty file, or a mapping refused; the caller reads it. */
static void map_text(FILE *f, char **map, size_t *len)
{
    struct stat sb;
    *map = NULL;
    int fd = fileno(f);
    if (fd < 0 || fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || sb.st_size <= 0 ||
        (uintmax_t)sb.st_size > SIZE_MAX)
        return;
    void *p = mmap(NULL, (size_t)sb.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED)
        return;
    posix_madvise(p, (size_t)sb.st_size, POSIX_MADV_SEQUENTIAL);
    *map = p;
    *len = (size_t)sb.st_size;
}

int hpfc_pfc_read_file(const char *path, hpfc_graph **out, hpfc_diag *diag)
{
    char *text = NULL, *map = NULL;
    size_t len = 0;
    int st = HPFC_OK;
    diag_clear(diag);
    if (out)
        *out = NULL;
    if (!path || !out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_pfc_read_file: NULL argument");
    errno = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return diag_set(diag, HPFC_E_IO, "cannot open %s: %s", path, strerror(errno));
    map_text(f, &map, &len);
    errno = 0;
    if (!map)
        st = read_stream(f, &text, &len);
    int read_errno = errno;
    fclose(f);
    if (st == HPFC_E_NOMEM)
        return diag_set(diag, st, "cannot read %s: out of memory", path);
    if (st)
        return diag_set(diag, st, "cannot read %s: %s", path,
                        strerror(read_errno ? read_errno : EIO));
    st = hpfc_pfc_parse(map ? map : text, len, out, diag);
    if (map)
        munmap(map, len);
    free(text);
    return st;
}

/* ------------------------------------------------------------------------
 * A text read in chunks (hpfc.h, "A .pfc text read in chunks")
 *
 * Each chunk runs pass 1 alone (hpfc_pfc_chunk_scan), then pass 1 and pass
 * 2 together once the whole text's d is known (hpfc_pfc_chunk_fill): the
 * same checks and the same exact scaling as hpfc_pfc_parse, line for line,
 * but for what a chunk cannot see (hpfc.h lists it).
 * ------------------------------------------------------------------------ */

/* Does the line [b, e) (its end of line excluded) hold a field? */
static bool line_has_field(const char *b, const char *e)
{
    if (e > b && e[-1] == '\r')
        e--;
    const char *hash = memchr(b, '#', (size_t)(e - b));
    for (const char *p = b; p < (hash ? hash : e); p++)
        if (!is_blank(*p))
            return true;
    return false;
}

/* The end of the first line that holds a field (the header's, in a valid
 * text), or the text's end. */
static size_t header_end(const char *text, size_t length)
{
    size_t pos = length >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    while (pos < length) {
        const char *nl = memchr(text + pos, '\n', length - pos);
        size_t end = nl ? (size_t)(nl - text) : length;
        if (line_has_field(text + pos, text + end))
            return nl ? end + 1 : length;
        pos = end + 1;
    }
    return length;
}

size_t hpfc_pfc_chunk_bounds(const char *text, size_t length, size_t count, size_t *bounds)
{
    if ((!text && length) || !bounds || count == 0)
        return 0;
    size_t n = 0, head = header_end(text, length), step = length / count, rest = length % count;
    bounds[0] = 0;
    for (size_t k = 1; k < count; k++) {
        /* k * length / count without overflow: rest < count */
        size_t at = step * k + (size_t)((double)rest * (double)k / (double)count);
        at = at < head ? head : at;
        if (at > 0 && at < length && text[at - 1] != '\n') {
            const char *nl = memchr(text + at, '\n', length - at);
            at = nl ? (size_t)(nl - text) + 1 : length;
        }
        if (at >= length)
            break;
        if (at > bounds[n])
            bounds[++n] = at;
    }
    bounds[++n] = length;
    return n;
}

static bool chunk_ok(const char *text, size_t length, size_t begin, size_t end)
{
    return (text || !length) && begin <= end && end <= length &&
           (begin == 0 || text[begin - 1] == '\n') && (end == length || text[end - 1] == '\n');
}

static void chunk_reader(pfc_reader *r, const char *text, size_t begin, size_t end, hpfc_diag *diag)
{
    memset(r, 0, sizeof *r);
    r->text = text ? text + begin : "";
    r->length = end - begin;
    r->diag = diag;
    r->chunk = true;
    r->inner = begin != 0;
}

int hpfc_pfc_chunk_scan(const char *text, size_t length, size_t begin, size_t end,
                        hpfc_pfc_chunk *out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!out || !chunk_ok(text, length, begin, end))
        return diag_set(diag, HPFC_E_ARG, "hpfc_pfc_chunk_scan: not a chunk of the text");
    memset(out, 0, sizeof *out);
    pfc_reader r;
    chunk_reader(&r, text, begin, end, diag);
    const char *b, *e;
    bool header_seen = r.inner;
    int st = HPFC_OK;
    r.pos = text_start(&r);
    while (!st && next_line(&r, &b, &e)) {
        if (!(st = check_encoding(&r, b, e)) && !(st = split_fields(&r, b, e)) && r.ntok)
            st = check_record(&r, &header_seen);
    }
    if (!st && !header_seen)
        st = fail(&r, HPFC_E_PFC_VERSION, last_line(&r), "end of input before the 'pfc 1' header");
    free(r.tok);
    if (st)
        return st;
    out->vertices = r.nv, out->edges = r.ne, out->points = r.np;
    out->digits = r.d > INT32_MAX ? INT32_MAX : (int32_t)r.d;
    return HPFC_OK;
}

static void box_add(int64_t box[4], const int64_t *xy)
{
    box[0] = xy[0] < box[0] ? xy[0] : box[0], box[2] = xy[0] > box[2] ? xy[0] : box[2];
    box[1] = xy[1] < box[1] ? xy[1] : box[1], box[3] = xy[1] > box[3] ? xy[1] : box[3];
}

static int chunk_changed(pfc_reader *r)
{
    return fail(r, HPFC_E_ARG, r->line, "the chunk is not the one scanned");
}

static int fill_vertex(pfc_reader *r, hpfc_pfc_fill *f, size_t k)
{
    int64_t *xy = f->vxy + 2 * k;
    int st = scale_token(r, &r->tok[1], &xy[0]);
    if (!st)
        st = scale_token(r, &r->tok[2], &xy[1]);
    if (!st)
        box_add(f->box, xy);
    return st;
}

/* An end of edge `k` (its record's field `which`) names a vertex of this
 * chunk's before it or of the chunks before. */
static int fill_edge_end(pfc_reader *r, const hpfc_pfc_fill *f, int which, uint32_t *out)
{
    char q[PFC_QUOTE_MAX + 4];
    uint64_t index = 0, defined = f->first_vertex + r->nv;
    parse_index(&r->tok[which], &index); /* checked by check_record */
    if (index < defined && index < (uint64_t)UINT32_MAX - 2) {
        *out = (uint32_t)index; /* defined < 2^32 - 2: the layout's bound */
        return HPFC_OK;
    }
    diag_edge(r, r->ne - 1);
    return fail(r, HPFC_E_VERTEX_INDEX, r->line,
                "edge names vertex %s but only %llu vertices are defined before it",
                quote(&r->tok[which], q), (unsigned long long)defined);
}

/* Edge k (the chunk's) and its n interior points, from point p on. */
static int fill_edge(pfc_reader *r, hpfc_pfc_fill *f, size_t k, size_t p, size_t n)
{
    int st = fill_edge_end(r, f, 1, &f->eu[k]);
    if (!st)
        st = fill_edge_end(r, f, 2, &f->ev[k]);
    for (size_t c = 0; !st && c < 2 * n; c++)
        st = scale_token(r, &r->tok[3 + c], &f->pts[2 * p + c]);
    for (size_t c = 0; !st && c < n; c++) {
        const int64_t *xy = f->pts + 2 * (p + c);
        box_add(f->box, xy);
        if (c && xy[0] == xy[-2] && xy[1] == xy[-1]) { /* the ends are the whole graph's check */
            diag_edge(r, k);
            st = fail(r, HPFC_E_ZERO_LENGTH, r->line,
                      "zero-length segment: edge points %zu and %zu are one point", c, c + 1);
        }
    }
    f->eoff[k] = f->first_point + p;
    return st;
}

/* One record of the chunk checked (pass 1) and filled (pass 2). */
static int fill_record(pfc_reader *r, hpfc_pfc_fill *f, const hpfc_pfc_chunk *scan, bool *header_seen)
{
    bool was_header = !*header_seen;
    size_t nv = r->nv, ne = r->ne, np = r->np;
    int st = check_record(r, header_seen);
    if (st || was_header)
        return st;
    if (r->d != f->digits || r->nv > scan->vertices || r->ne > scan->edges || r->np > scan->points)
        return chunk_changed(r);
    if (r->nv > nv)
        return fill_vertex(r, f, nv);
    return fill_edge(r, f, ne, np, r->np - np);
}

int hpfc_pfc_chunk_fill(const char *text, size_t length, size_t begin, size_t end,
                        const hpfc_pfc_chunk *scan, hpfc_pfc_fill *fill, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!scan || !fill || !chunk_ok(text, length, begin, end) ||
        (scan->vertices && !fill->vxy) || (scan->edges && (!fill->eu || !fill->ev || !fill->eoff)) ||
        (scan->points && !fill->pts) || fill->digits < scan->digits || fill->digits < 0)
        return diag_set(diag, HPFC_E_ARG, "hpfc_pfc_chunk_fill: not a scanned chunk and its arrays");
    fill->box[0] = fill->box[1] = INT64_MAX, fill->box[2] = fill->box[3] = INT64_MIN;
    pfc_reader r;
    chunk_reader(&r, text, begin, end, diag);
    if (fill->digits > PFC_MAX_FRAC_DIGITS)
        return fail(&r, HPFC_E_LIMIT, 1,
                    "coordinates have %ld significant fractional digits; at most %d are supported",
                    (long)fill->digits, PFC_MAX_FRAC_DIGITS);
    r.d = fill->digits;
    const char *b, *e;
    bool header_seen = r.inner;
    int st = HPFC_OK;
    r.pos = text_start(&r);
    while (!st && next_line(&r, &b, &e)) {
        if (!(st = check_encoding(&r, b, e)) && !(st = split_fields(&r, b, e)) && r.ntok)
            st = fill_record(&r, fill, scan, &header_seen);
    }
    if (!st && (r.nv != scan->vertices || r.ne != scan->edges || r.np != scan->points || !header_seen))
        st = chunk_changed(&r);
    free(r.tok);
    return st;
}
