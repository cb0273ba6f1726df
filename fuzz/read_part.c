/*
 * read_part: a part file (spec/part-format.md), the tree of one part of a
 * split build (hpfc_build_part) as another process hands it to the merge.
 *
 * The input is a part file. Its trailing CRC-32C is set anew over the
 * input first (the library has no flag to skip it), so that mutations reach
 * the structure. Then hpfc_tree_read_part_memory; when it accepts, the
 * tree's pixels through hpfc_tree_get_pixel, the file written again
 * (part_serialize), the part merged alone (which succeeds only when it
 * holds every root pixel) and the merged tree serialised with LABL. Every
 * input is also written to a file and joined from there by
 * hpfc_tree_merge_files (the part read in place from its mapping, the
 * joined tree a view over it).
 *
 * Oracle: the reader's statuses only (magic, version, corrupt, memory), and a diagnostic with every failure; an
 * accepted file is canonical: written again it gives the input's bytes
 * (the reader accepts only what the builder can make, so nothing it
 * ignores can differ); its pixels are words of the grammar's symbols with
 * edges below the map's count, or refined pixels whose child is an image
 * of the next level; a merge of the part alone succeeds exactly when no
 * root pixel is another part's; the file merge gives the status of the
 * read, or else of the copying merge, and its view serialises to the
 * copying merge's bytes (both layouts), or fails where that one fails;
 * serialised with the faces a root pixel at a time (faces_by_root) it
 * gives a known status with a diagnostic. The join without the
 * components' count (hpfc_tree_merge_files_uncounted) gives the counted
 * join's status, its counts but F and C, and its bytes with the faces by
 * root. Each of the view's two
 * serialisations is also written to a file (hpfc_tree_write_fd, made in
 * the file's own pages): the same status and the same bytes.
 */
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "format.h"
#include "input.h"
#include "part_file.h"

/* What reading a part file may answer. */
static bool read_status(int st)
{
    return st == HPFC_OK || st == HPFC_E_NOMEM || st == HPFC_E_MAGIC || st == HPFC_E_VERSION ||
           st == HPFC_E_CORRUPT;
}

static bool has_other_parts_pixel(const hpfc_tree *t, const hpfc_tree_info *info)
{
    for (uint32_t j = 0; j < info->root_rows; j++)
        for (uint32_t i = 0; i < info->root_cols; i++) {
            hpfc_tree_pixel px;
            if (hpfc_tree_get_pixel(t, 0, 0, i, j, &px) == HPFC_E_ARG)
                return true;
        }
    return false;
}

static void check_pixels(const hpfc_tree *t, const hpfc_tree_info *info)
{
    for (uint32_t l = 0; l < info->levels; l++) {
        size_t images = hpfc_tree_image_count(t, l), visited = 0;
        uint32_t cols = l ? info->cols : info->root_cols, rows = l ? info->rows : info->root_rows;
        for (size_t im = 0; im < images && visited < 4096; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++, visited++) {
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(t, l, im, i, j, &px);
                    FUZZ_CHECK(st == HPFC_OK || (st == HPFC_E_ARG && l == 0));
                    if (st)
                        continue;
                    if (px.type == HPFC_PIXEL_REFINED) {
                        FUZZ_CHECK(px.child < hpfc_tree_image_count(t, l + 1));
                        continue;
                    }
                    FUZZ_CHECK(px.word_len >= 4 && px.word_len <= info->max_word_symbols + 4);
                    for (uint32_t k = 0; k < px.word_len; k++)
                        FUZZ_CHECK(strchr("+=[]()Y", px.word[k]) != NULL);
                    for (uint32_t k = 0; k + 4 < px.word_len; k++)
                        FUZZ_CHECK(px.cross_edge[k] < info->edges);
                }
    }
}

/* The joined tree serialised with LABL in `layout`: its status, *bytes
 * (hpfc_free) when it succeeds. */
static int serialize(const hpfc_tree *joined, int layout, int by_root, uint8_t **bytes, size_t *size)
{
    hpfc_diag d;
    hpfc_write_options o = {.face_labels = 1, .layout = layout, .faces_by_root = by_root};
    int st = hpfc_tree_serialize(joined, &o, bytes, size, &d);
    fuzz_check_diag(&d, st); /* a map of hostile words may fail to number its faces */
    return st;
}

/* A scratch file for the process (unlinked at once), opened for reading
 * and writing: -1 when it cannot be made. */
static int scratch_fd(const char *what)
{
    char name[64];
    snprintf(name, sizeof name, "/tmp/fuzz-read-part-%ld.%s", (long)getpid(), what);
    int fd = open(name, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd >= 0)
        unlink(name);
    return fd;
}

/* The joined tree written as serialize() makes it, but to a file, which
 * the writer makes in its own pages (write_in_place): the same status and,
 * when it succeeds, the same bytes as `want`. */
static void check_written(const hpfc_tree *joined, int layout, int by_root, int want_st,
                          const uint8_t *want, size_t want_size)
{
    static int fd = -1;
    if (fd < 0 && (fd = scratch_fd("hpfc")) < 0)
        return;
    hpfc_diag d;
    hpfc_write_options o = {.face_labels = 1, .layout = layout, .faces_by_root = by_root};
    int st = hpfc_tree_write_fd(joined, &o, fd, &d);
    fuzz_check_diag(&d, st);
    if (st == HPFC_E_NOMEM || want_st == HPFC_E_NOMEM)
        return;
    FUZZ_CHECK(st == want_st);
    if (st)
        return;
    struct stat sb;
    FUZZ_CHECK(fstat(fd, &sb) == 0 && (size_t)sb.st_size == want_size);
    uint8_t *got = malloc(want_size ? want_size : 1);
    FUZZ_CHECK(got && pread(fd, got, want_size, 0) == (ssize_t)want_size &&
               memcmp(got, want, want_size) == 0);
    free(got);
}

/* The input as a part file on disk, for hpfc_tree_merge_files: one file
 * for the process (unlinked at once, named through /proc), rewritten for
 * each input. */
static const char *part_path(const uint8_t *data, size_t size)
{
    static char path[64];
    static int fd = -1;
    if (fd < 0) {
        if ((fd = scratch_fd("part")) < 0)
            return NULL;
        snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    }
    if (ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != (ssize_t)size)
        return NULL;
    return path;
}

/* The part joined alone from its file without the components' count
 * (hpfc_tree_merge_files_uncounted): the counted join's status `want_st`
 * and, when it succeeds (`counted`), its counts but F and C (0), and its
 * bytes with the faces a root pixel at a time (as the Dask client writes
 * them), status and bytes. */
static void check_uncounted(const char *path, int want_st, const hpfc_tree *counted)
{
    hpfc_tree *view = NULL;
    hpfc_diag d;
    int st = hpfc_tree_merge_files_uncounted(&path, 1, &view, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK((st == HPFC_OK) == (view != NULL));
    if (st == HPFC_E_NOMEM || want_st == HPFC_E_NOMEM) {
        hpfc_tree_free(view);
        return;
    }
    FUZZ_CHECK(st == want_st);
    if (st) {
        hpfc_tree_free(view);
        return;
    }
    hpfc_tree_info a, b;
    hpfc_tree_get_info(counted, &a);
    hpfc_tree_get_info(view, &b);
    FUZZ_CHECK(b.faces == 0 && b.components == 0 && a.vertices == b.vertices && a.edges == b.edges &&
               a.levels == b.levels && a.word_pixels == b.word_pixels);
    uint8_t *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    int sx = serialize(counted, HPFC_LAYOUT_COMPACT, 1, &x, &nx);
    int sy = serialize(view, HPFC_LAYOUT_COMPACT, 1, &y, &ny);
    if (sx != HPFC_E_NOMEM && sy != HPFC_E_NOMEM)
        FUZZ_CHECK(sx == sy && nx == ny && (sx || memcmp(x, y, nx) == 0));
    hpfc_free(x);
    hpfc_free(y);
    hpfc_tree_free(view);
}

/* The part joined alone from its file: the read's status (read_st), or
 * else the copying merge's (merge_st), and then the copying merge's bytes
 * (`joined`'s) in both layouts. */
static void merge_file_alone(const uint8_t *data, size_t size, int read_st, int merge_st,
                             const hpfc_tree *joined)
{
    const char *path = part_path(data, size);
    if (!path)
        return;
    hpfc_tree *view = NULL;
    hpfc_diag d;
    int st = hpfc_tree_merge_files(&path, 1, &view, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK((st == HPFC_OK) == (view != NULL));
    if (st != HPFC_E_NOMEM)
        FUZZ_CHECK(st == (read_st ? read_st : merge_st) ||
                   (read_st == HPFC_E_NOMEM || merge_st == HPFC_E_NOMEM));
    check_uncounted(path, st, view);
    if (st || !joined) {
        hpfc_tree_free(view);
        return;
    }
    for (int layout = HPFC_LAYOUT_PAPER; layout <= HPFC_LAYOUT_COMPACT; layout++) {
        uint8_t *a = NULL, *b = NULL;
        size_t na = 0, nb = 0;
        int sa = serialize(joined, layout, 0, &a, &na), sb = serialize(view, layout, 0, &b, &nb);
        if (sa != HPFC_E_NOMEM && sb != HPFC_E_NOMEM)
            FUZZ_CHECK(sa == sb && na == nb && (sa || memcmp(a, b, na) == 0));
        check_written(view, layout, 0, sb, b, nb);
        hpfc_free(a);
        hpfc_free(b);
        /* the faces a root pixel at a time: a known status (hostile words
         * may number differently where a root's side is inconsistent),
         * the same written in place */
        b = NULL;
        sb = serialize(view, layout, 1, &b, &nb);
        check_written(view, layout, 1, sb, b, nb);
        hpfc_free(b);
    }
    hpfc_tree_free(view);
}

/* The part merged alone (hpfc_tree_merge): its status, *joined the tree
 * when it succeeds. */
static int merge_alone(hpfc_tree *t, const hpfc_tree_info *info, hpfc_tree **joined)
{
    hpfc_diag d;
    int st = hpfc_tree_merge(&t, 1, joined, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK(fuzz_known_status(st));
    if (has_other_parts_pixel(t, info))
        FUZZ_CHECK(st == HPFC_E_ARG);
    return st;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    if (size >= PART_CRC_SIZE)
        le_store(copy + size - PART_CRC_SIZE, 4, crc32c_update(0, copy, size - PART_CRC_SIZE));
    hpfc_tree *t = NULL;
    hpfc_diag d;
    int st = hpfc_tree_read_part_memory(copy, size, &t, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK(read_status(st));
    FUZZ_CHECK((st == HPFC_OK) == (t != NULL));
    hpfc_tree *joined = NULL;
    int merge_st = HPFC_E_ARG;
    if (!st) {
        hpfc_tree_info info;
        hpfc_tree_get_info(t, &info);
        check_pixels(t, &info);
        uint8_t *again = NULL;
        size_t again_size = 0;
        FUZZ_CHECK(part_serialize(t, &again, &again_size, &d) == HPFC_OK);
        FUZZ_CHECK(again_size == size && memcmp(again, copy, size) == 0);
        free(again);
        merge_st = merge_alone(t, &info, &joined);
    }
    merge_file_alone(copy, size, st, merge_st, joined);
    hpfc_tree_free(joined);
    hpfc_tree_free(t);
    free(copy);
    return 0;
}
