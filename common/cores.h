/*
 * cores.h: how many threads the tools give the library's steps that share
 * their work (hpfc_faces_build_threads): one a core the machine has online,
 * up to 8 (past that the numbering waits on memory, not on the cores).
 * Header-only.
 */
#ifndef HPFC_TOOLS_CORES_H
#define HPFC_TOOLS_CORES_H

#include <unistd.h>

static inline unsigned default_threads(void)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    return cores < 1 ? 1 : cores > 8 ? 8 : (unsigned)cores;
}

#endif
