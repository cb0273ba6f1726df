/*
 * args.c: hpfc-inspect's view arguments, parsed before the file is opened
 * (decimals kept exact, pixel paths), and the one-line failure reason every
 * view returns.
 */
#include "views.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

int view_fail(char *why, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, VIEW_WHY, fmt, ap);
    va_end(ap);
    return VIEW_FAIL;
}

int view_fail_status(char *why, const char *what, int st)
{
    return view_fail(why, "%s: %s", what, hpfc_strerror(st));
}

/* ---- options ------------------------------------------------------------------ */

/* The value of option `name` at argv[*i], as "--name VALUE" or
 * "--name=VALUE"; NULL when argv[*i] is another option. *missing is set when
 * the option is there without its value. A separate VALUE that looks like an
 * option counts as missing: "--export-graph --json FILE" is a slip, and
 * writing a file named "--json" would hide it (--name=-x still works). */
const char *option_value(int argc, char **argv, int *i, const char *name, int *missing)
{
    size_t n = strlen(name);
    const char *arg = argv[*i];
    if (strncmp(arg, name, n) != 0)
        return NULL;
    if (arg[n] == '=')
        return arg + n + 1;
    if (arg[n] != '\0')
        return NULL;
    if (*i + 1 >= argc || (argv[*i + 1][0] == '-' && argv[*i + 1][1] != '\0')) {
        *missing = 1;
        return NULL;
    }
    return argv[++*i];
}

/* A value that starts with '-' and then a digit or a point is a negative
 * number, not a slip: "--locate -5,3 FILE". */
const char *option_numeric_value(int argc, char **argv, int *i, const char *name, int *missing)
{
    const char *next = *i + 1 < argc ? argv[*i + 1] : "";
    if (strcmp(argv[*i], name) == 0 && next[0] == '-' &&
        ((next[1] >= '0' && next[1] <= '9') || next[1] == '.'))
        return argv[++*i];
    return option_value(argc, argv, i, name, missing);
}

/* ---- decimals ----------------------------------------------------------------- */

static size_t scan_digits(const char *s, size_t len, size_t p)
{
    while (p < len && isdigit((unsigned char)s[p]))
        p++;
    return p;
}

/* Appends digit c to the significand; leading zeros are dropped, so only
 * the significant digits count against the limit. */
static int push_digit(decimal *d, size_t *nd, char c)
{
    if (*nd == 0 && c == '0')
        return 0;
    if (*nd + 1 >= sizeof d->digits)
        return -1;
    d->digits[(*nd)++] = c;
    return 0;
}

static int parse_exponent(const char *s, size_t len, size_t p, long *e)
{
    int neg = 0;
    if (p < len && (s[p] == '+' || s[p] == '-'))
        neg = s[p++] == '-';
    size_t q = scan_digits(s, len, p);
    if (q == p || q != len)
        return -1;
    *e = 0;
    for (; p < q; p++)
        if (*e < 100000)
            *e = *e * 10 + (s[p] - '0');
    if (neg)
        *e = -*e;
    return 0;
}

int decimal_parse(const char *s, size_t len, decimal *d)
{
    memset(d, 0, sizeof *d);
    size_t p = 0, nd = 0;
    long exp10 = 0, e = 0;
    if (p < len && (s[p] == '+' || s[p] == '-'))
        d->neg = s[p++] == '-';
    size_t int_end = scan_digits(s, len, p), frac_end = int_end;
    for (size_t k = p; k < int_end; k++)
        if (push_digit(d, &nd, s[k]))
            return -1;
    if (int_end < len && s[int_end] == '.') {
        frac_end = scan_digits(s, len, int_end + 1);
        for (size_t k = int_end + 1; k < frac_end; k++) {
            if (push_digit(d, &nd, s[k]))
                return -1;
            exp10--;
        }
    }
    size_t ndig = (int_end - p) + (frac_end > int_end ? frac_end - int_end - 1 : 0);
    if (ndig == 0)
        return -1;
    if (frac_end < len) {
        if ((s[frac_end] != 'e' && s[frac_end] != 'E') || parse_exponent(s, len, frac_end + 1, &e))
            return -1;
    }
    while (nd > 0 && d->digits[nd - 1] == '0') {
        nd--;
        exp10++;
    }
    d->digits[nd] = '\0';
    exp10 += e;
    if (exp10 > 1000000 || exp10 < -1000000)
        return -1;
    d->exp10 = nd ? (int32_t)exp10 : 0;
    if (!nd)
        d->neg = 0;
    char tmp[96];
    snprintf(tmp, sizeof tmp, "%s%se%d", d->neg ? "-" : "", nd ? d->digits : "0", (int)d->exp10);
    d->value = strtod(tmp, NULL);
    return 0;
}

int decimal_list_parse(const char *text, decimal *out, int n)
{
    const char *p = text;
    for (int k = 0; k < n; k++) {
        const char *end = strchr(p, ',');
        if ((k < n - 1) != (end != NULL))
            return -1;
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (decimal_parse(p, len, &out[k]))
            return -1;
        p = end ? end + 1 : p + len;
    }
    return 0;
}

int decimal_floor_lattice(const decimal *d, int32_t unit_exp10, int64_t *out)
{
    long k = (long)d->exp10 - unit_exp10;
    long nd = (long)strlen(d->digits);
    long int_digits = nd + k; /* digits before the point after scaling */
    uint64_t mag = 0;
    bool frac = false;
    if (int_digits > 19)
        return -1;
    for (long i = 0; i < int_digits; i++) {
        uint64_t digit = i < nd ? (uint64_t)(d->digits[i] - '0') : 0;
        if (mag > (UINT64_MAX - digit) / 10)
            return -1;
        mag = mag * 10 + digit;
    }
    frac = nd > (int_digits > 0 ? int_digits : 0); /* trailing digits are non-zero */
    if (d->neg && frac)
        mag++;
    if (mag > (uint64_t)INT64_MAX)
        return -1;
    *out = d->neg ? -(int64_t)mag : (int64_t)mag;
    return 0;
}

int decimal_fraction_digits(const decimal *d)
{
    return d->exp10 >= 0 ? 0 : d->exp10 < -17 ? 17 : -d->exp10;
}

void view_decimal_text(int64_t v, int32_t e, char *buf, size_t cap)
{
    uint64_t mag = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    char digits[32];
    int n = snprintf(digits, sizeof digits, "%llu", (unsigned long long)mag);
    const char *sign = v < 0 ? "-" : "";
    if (e >= 0 || mag == 0) {
        snprintf(buf, cap, "%s%s%.*s", sign, digits, mag ? (int)(e > 40 ? 40 : e) : 0,
                 "0000000000000000000000000000000000000000");
        return;
    }
    int frac = -e;
    if (n <= frac)
        snprintf(buf, cap, "%s0.%.*s%s", sign, frac - n, "000000000000000000000000000000000000000",
                 digits);
    else
        snprintf(buf, cap, "%s%.*s.%s", sign, n - frac, digits, digits + n - frac);
}

/* A lattice coordinate as a JSON number in user units: exact while the
 * value has at most 15-17 significant digits (jsonw writes doubles). */
/* ---- pixel paths ------------------------------------------------------------- */

static int parse_u32(const char **p, uint32_t *out)
{
    const char *s = *p;
    uint64_t v = 0;
    if (!isdigit((unsigned char)*s))
        return -1;
    for (; isdigit((unsigned char)*s); s++) {
        v = v * 10 + (uint64_t)(*s - '0');
        if (v > UINT32_MAX)
            return -1;
    }
    *out = (uint32_t)v;
    *p = s;
    return 0;
}

int pixel_path_parse(const char *text, pixel_path *out, char *why, size_t cap)
{
    const char *p = text;
    memset(out, 0, sizeof *out);
    for (;;) {
        if (out->levels == HPFC_MAX_LEVELS) {
            snprintf(why, cap, "more than %d levels", HPFC_MAX_LEVELS);
            return -1;
        }
        uint32_t *ij = out->ij[out->levels];
        if (parse_u32(&p, &ij[0]) || *p++ != ',' || parse_u32(&p, &ij[1])) {
            snprintf(why, cap, "expected i,j per level joined by '/', e.g. 3,5/1,0");
            return -1;
        }
        out->levels++;
        if (*p == '\0')
            return 0;
        if (*p++ != '/') {
            snprintf(why, cap, "expected i,j per level joined by '/', e.g. 3,5/1,0");
            return -1;
        }
    }
}

/* The pixel a path names, or VIEW_FAIL with the reason. */
