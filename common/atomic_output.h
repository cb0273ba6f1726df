/*
 * atomic_output.h: how every tool writes an output file (hpfc-pack's
 * .hpfc, hpfc-inspect's --export-graph, --export, --export-faces and
 * --render pictures and world files): one routine, one policy. (GDAL
 * drivers write into memory first, for the reason export_gis.c gives, and
 * each file they make comes out through here.)
 *
 * The bytes go to a temporary file in OUT's directory (so that the rename
 * stays on one file system), which is flushed and fsync'd, renamed over
 * OUT, and then OUT's directory is fsync'd, so that after a crash OUT is
 * either the old file or the whole new one. On any failure (a full disk, a
 * file size limit, a read-only directory, a writer that gives up) the
 * temporary file is removed and an existing OUT is left as it was.
 *
 * A process killed outright (SIGKILL, a power cut) cannot clean up. Where
 * the system allows it (Linux O_TMPFILE) the temporary file has no name
 * until it is complete, so a kill leaves nothing; elsewhere, and in the
 * instant between naming a complete file and renaming it, it leaves a
 * hidden ".OUT.<pid>.<hex>.tmp", which the next write of
 * the same OUT removes once process <pid> is gone. OUT itself is never
 * partial.
 *
 * A file size limit (ulimit -f) would kill the program with SIGXFSZ at the
 * first byte past it; atomic_output_open ignores that signal so that the
 * write fails with EFBIG and the output is cleaned up like any other
 * failure.
 *
 * Messages go to a caller's `why` buffer of ATOMIC_WHY bytes as one line,
 * "OUT: cannot write: No space left on device", for the tool to print
 * after its name.
 */
#ifndef HPFC_ATOMIC_OUTPUT_H
#define HPFC_ATOMIC_OUTPUT_H

#include <stddef.h>
#include <stdio.h>

#define ATOMIC_WHY 512

typedef struct atomic_output {
    char *path;       /* OUT, as given */
    char *dir;        /* OUT's directory: ".", "/" or the part before the last '/' */
    const char *base; /* OUT's last name, inside path */
    char *tmp;        /* the temporary file's name; NULL while unnamed */
    int fd;           /* the temporary file */
    FILE *fp;         /* atomic_output_stream's stream over fd, once asked for */
} atomic_output;

/* Creates OUT's temporary file. 0, or 1 with why[] filled. */
int atomic_output_open(atomic_output *o, const char *path, char *why);

/* A stdio stream over the temporary file (owned by o; NULL with errno
 * when out of memory). */
FILE *atomic_output_stream(atomic_output *o);

/* A path that opens the temporary file (written so far) for reading:
 * its name, or, when it has none yet (O_TMPFILE), its descriptor under
 * /proc/self/fd, formatted into buf. */
const char *atomic_output_read_path(const atomic_output *o, char *buf, size_t cap);

/* Makes the temporary file OUT: flush, fsync, rename, fsync of the
 * directory. 0, or 1 with why[] filled and the temporary file removed. o
 * is released either way. */
int atomic_output_commit(atomic_output *o, char *why);

/* Removes the temporary file and releases o (any state after a
 * successful open, or a zeroed o: nothing to do). */
void atomic_output_discard(atomic_output *o);

/* The whole of `size` bytes as OUT, by open, write and commit. */
int atomic_output_write(const char *path, const void *data, size_t size, char *why);

/* Whether OUT could be created: makes and removes a temporary file beside
 * it, for a tool that checks before a long run. 0, or 1 with why[]. */
int atomic_output_check(const char *path, char *why);

#endif
