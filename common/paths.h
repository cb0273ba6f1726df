/*
 * paths.h: questions the tools ask about the paths a user gives them
 * before they write anything. Header-only.
 */
#ifndef HPFC_TOOLS_PATHS_H
#define HPFC_TOOLS_PATHS_H

#include <sys/stat.h>

/* Whether two paths name one existing file (through links too): writing
 * an output over the input would destroy it. */
static inline int same_file(const char *p, const char *q)
{
    struct stat a, b;
    return stat(p, &a) == 0 && stat(q, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

#endif
