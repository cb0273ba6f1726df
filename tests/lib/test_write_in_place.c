/*
 * A tree written to disk with LABL is made in the file's own pages
 * (write.c's write_in_place): the pools written, read back under a
 * provisional header for their faces, LABL placed and made in place, SHIX
 * from it. The oracle is hpfc_tree_serialize, which builds every section
 * in memory first: the same bytes, for
 *   - hpfc_tree_write_file and hpfc_tree_write_fd on a descriptor open for
 *     reading and writing (in place), and on one open for writing only
 *     (not mappable: the sections built in memory, then written);
 *   - maps of the generators and the special cases, both layouts, root
 *     grids 1x1, 4x4 and 5x3, with the faces numbered whole and a root
 *     pixel at a time, with GEOM, a CRS and a feature table;
 * the faces handed out (faces_out) attach to the file written; and a file
 * size limit met at each step of the write (the pools, LABL, SHIX) fails
 * it with HPFC_E_IO and leaves nothing in the directory.
 */
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "file_helpers.h"
#include "gen.h"
#include "hpfc.h"

static size_t writes_checked, limits_checked;

static uint8_t *read_fd(int fd, size_t *size)
{
    struct stat sb;
    if (fstat(fd, &sb) != 0)
        return NULL;
    *size = (size_t)sb.st_size;
    uint8_t *b = malloc(*size ? *size : 1);
    if (b && pread(fd, b, *size, 0) != (ssize_t)*size) {
        free(b);
        return NULL;
    }
    return b;
}

static bool path_equals(const char *path, const uint8_t *want, size_t size)
{
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return false;
    size_t got_size = 0;
    uint8_t *got = read_fd(fd, &got_size);
    close(fd);
    bool same = got && got_size == size && memcmp(got, want, size) == 0;
    free(got);
    return same;
}

/* hpfc_tree_write_fd into `path` opened with `mode` over junk: the bytes
 * `want`. */
static void check_fd(const hpfc_tree *t, const hpfc_write_options *o, const char *path, int mode,
                     const uint8_t *want, size_t size)
{
    int fd = open(path, O_CREAT | O_TRUNC | mode, 0644);
    CHECK(fd >= 0);
    if (fd < 0)
        return;
    static const uint8_t junk[4096] = {0xa5};
    CHECK_EQ_INT(write(fd, junk, sizeof junk), (ssize_t)sizeof junk);
    hpfc_diag d;
    int st = hpfc_tree_write_fd(t, o, fd, &d);
    if (st)
        fprintf(stderr, "hpfc_tree_write_fd: %s\n", d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    close(fd);
    CHECK(path_equals(path, want, size));
    remove(path);
}

/* The faces handed out by the write in place attach to the file it wrote
 * and number as many faces as the serialiser's. */
static void check_faces_out(const hpfc_tree *t, const hpfc_write_options *o, const char *path,
                            uint64_t faces)
{
    hpfc_write_options with = *o;
    hpfc_faces *fc = NULL;
    with.faces_out = &fc;
    CHECK_EQ_INT(hpfc_tree_write_file(t, &with, path, NULL), HPFC_OK);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    CHECK(fc && f && hpfc_faces_attach(fc, f) == HPFC_OK && hpfc_faces_face_count(fc) == faces);
    hpfc_faces_free(fc);
    hpfc_close(f);
    remove(path);
}

static int dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

/* A file size limit of `limit` bytes (below the file's): the write fails
 * with HPFC_E_IO and leaves nothing. */
static void check_limit(const hpfc_tree *t, const hpfc_write_options *o, const char *dir,
                        const char *path, rlim_t limit)
{
    struct rlimit old, small;
    if (getrlimit(RLIMIT_FSIZE, &old) != 0)
        return;
    void (*handler)(int) = signal(SIGXFSZ, SIG_IGN);
    small = old;
    small.rlim_cur = limit;
    CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &small), 0);
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_write_file(t, o, path, &d), HPFC_E_IO);
    CHECK(strstr(d.message, "cannot write") != NULL);
    CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, handler);
    CHECK_EQ_INT(dir_entries(dir), 0);
    limits_checked++;
}

/* Where the write in place grows its file: past the pools, past LABL
 * and GEOM, then SHIX (the file's directory says where each lies). */
static void check_limits(const hpfc_tree *t, const hpfc_write_options *o, const char *dir,
                         const char *path, const uint8_t *want, size_t size)
{
    hpfc_file *f = NULL;
    if (hpfc_open_memory(want, size, 0, &f) != HPFC_OK)
        return;
    hpfc_level_info last;
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    hpfc_file_get_level(f, fi.levels - 1, &last);
    hpfc_close(f);
    uint64_t pools_end = last.pool_offset + (last.pool_bits + 7) / 8;
    check_limit(t, o, dir, path, 64);
    check_limit(t, o, dir, path, (rlim_t)pools_end + 8); /* LABL's growth */
    check_limit(t, o, dir, path, (rlim_t)size - 1);      /* SHIX's */
}

static void check_options(const hpfc_tree *t, const hpfc_write_options *o, const char *dir,
                          bool limits)
{
    char path[256];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    uint8_t *want = NULL;
    size_t size = 0;
    hpfc_faces *fc = NULL;
    hpfc_write_options serial = *o;
    serial.faces_out = &fc;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &serial, &want, &size, NULL), HPFC_OK);
    if (!want)
        return;
    hpfc_diag d;
    int st = hpfc_tree_write_file(t, o, path, &d);
    if (st)
        fprintf(stderr, "hpfc_tree_write_file: %s\n", d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    CHECK(path_equals(path, want, size));
    remove(path);
    check_fd(t, o, path, O_RDWR, want, size);   /* in place */
    check_fd(t, o, path, O_WRONLY, want, size); /* in memory, then written */
    check_faces_out(t, o, path, fc ? hpfc_faces_face_count(fc) : 0);
    if (limits)
        check_limits(t, o, dir, path, want, size);
    CHECK_EQ_INT(dir_entries(dir), 0);
    writes_checked++;
    hpfc_faces_free(fc);
    hpfc_free(want);
}

static void check_map(const hpfc_graph *g, const char *dir, bool limits)
{
    static const struct {
        uint32_t root_cols, root_rows, cols, rows;
    } grids[] = {{1, 1, 2, 2}, {4, 4, 2, 2}, {5, 3, 3, 2}};
    for (size_t k = 0; k < sizeof grids / sizeof *grids; k++)
        for (int layout = 0; layout < 2; layout++) {
            hpfc_build_params p;
            hpfc_build_params_default(&p);
            p.root_cols = grids[k].root_cols, p.root_rows = grids[k].root_rows;
            p.cols = grids[k].cols, p.rows = grids[k].rows;
            hpfc_tree *t = NULL;
            if (hpfc_build(g, &p, &t, NULL) != HPFC_OK)
                continue; /* a build's failure is test_build's */
            hpfc_write_options o = {.layout = layout ? HPFC_LAYOUT_COMPACT : HPFC_LAYOUT_PAPER,
                                    .face_labels = 1};
            check_options(t, &o, dir, limits && k == 1);
            o.faces_by_root = 1;
            check_options(t, &o, dir, false);
            o.faces_by_root = 0;
            o.geometry = g, o.crs = "EPSG:3857", o.threads = 2;
            check_options(t, &o, dir, limits && k == 2);
            /* as a merge with its graph mapped writes: GEOM planned beside
             * faces numbered a root pixel at a time */
            o.faces_by_root = 1;
            check_options(t, &o, dir, false);
            o.faces_by_root = 0;
            /* a feature table with FEAT's faces: SHIX gains its feature table */
            uint8_t *plain = NULL;
            size_t size = 0;
            hpfc_file *f = NULL;
            hpfc_faces *fc = NULL;
            if (hpfc_tree_serialize(t, &o, &plain, &size, NULL) == HPFC_OK &&
                hpfc_open_memory(plain, size, 0, &f) == HPFC_OK &&
                hpfc_faces_build(f, &fc) == HPFC_OK) {
                feat_fixture x;
                feat_fixture_make(&x, (uint32_t)hpfc_faces_face_count(fc));
                o.features = &x.t;
                check_options(t, &o, dir, false);
                free(x.start), free(x.link);
            }
            hpfc_faces_free(fc);
            hpfc_close(f);
            hpfc_free(plain);
            hpfc_tree_free(t);
        }
}

int main(void)
{
    char dir[] = "/tmp/hpfc-test-in-place-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    for (int k = 0; gen_special_name(k); k++) {
        hpfc_graph *g = NULL;
        if (gen_special(k, &g) == HPFC_OK)
            check_map(g, dir, k < 3);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay(seed, 30 * seed * seed, 100000, 0.3, &g) == HPFC_OK)
            check_map(g, dir, seed == 2);
        hpfc_graph_free(g);
        g = NULL;
        if (gen_polyline(seed, 40 * seed * seed, 100000, 0.5, &g) == HPFC_OK)
            check_map(g, dir, false);
        hpfc_graph_free(g);
    }
    CHECK_EQ_INT(rmdir(dir), 0); /* empty: nothing stray was left */
    printf("write_in_place: %zu writes, %zu size limits checked\n", writes_checked, limits_checked);
    CHECK(writes_checked > 100 && limits_checked > 10);
    return check_report("write_in_place");
}
