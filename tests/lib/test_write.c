/*
 * Writing files (hpfc_tree_write_file, hpfc_file_serialize,
 * hpfc_file_write_file; spec/hpfc-format.md): the atomic writer made to fail
 * (missing directory, file size limit, a directory as target, no write
 * permission) leaves the old file byte-identical and no temporary;
 * hpfc_open maps what was written; a file serialised again with other
 * optional sections equals the tree writer's bytes.
 */
#include <dirent.h>
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

/* ---- files: atomic writes, hpfc_open -------------------------------------------------- */

static uint8_t *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    uint8_t *buf = malloc(cap);
    for (size_t got; (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap)
            buf = realloc(buf, cap *= 2);
    }
    fclose(f);
    *size = n;
    return buf;
}

static bool file_equals(const char *path, const uint8_t *want, size_t size)
{
    size_t n = 0;
    uint8_t *got = read_all(path, &n);
    bool same = got && n == size && memcmp(got, want, size) == 0;
    free(got);
    return same;
}

/* Number of entries in dir, "." and ".." excluded. */
static int dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    if (!d)
        return -1;
    for (struct dirent *de; (de = readdir(d));)
        n += strcmp(de->d_name, ".") && strcmp(de->d_name, "..");
    closedir(d);
    return n;
}

static void test_write_file(void)
{
    char dir[] = "/tmp/hpfc-test-write-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], sub[256], bad[256];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    snprintf(sub, sizeof sub, "%s/sub", dir);
    snprintf(bad, sizeof bad, "%s/no/such/dir/map.hpfc", dir);
    hpfc_tree *a = special_tree(GEN_SPECIAL_TRIANGLE, 4), *b = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!a || !b)
        return;
    size_t size_a, size_b;
    uint8_t *buf_a = serialize(a, NULL, &size_a), *buf_b = serialize(b, "EPSG:4326", &size_b);
    hpfc_diag d;
    const hpfc_write_options plain = {.layout = check_layout};

    /* a missing directory: a clean failure, nothing created */
    CHECK_EQ_INT(hpfc_tree_write_file(a, &plain, bad, &d), HPFC_E_IO);
    CHECK_EQ_INT(d.status, HPFC_E_IO);
    CHECK_EQ_INT(dir_entries(dir), 0);

    /* a new file, then a replacement */
    CHECK_EQ_INT(hpfc_tree_write_file(a, &plain, path, &d), HPFC_OK);
    CHECK(file_equals(path, buf_a, size_a));
    CHECK_EQ_INT(dir_entries(dir), 1);
    hpfc_write_options opts = {.crs = "EPSG:4326", .layout = check_layout};
    CHECK_EQ_INT(hpfc_tree_write_file(b, &opts, path, &d), HPFC_OK);
    CHECK(file_equals(path, buf_b, size_b));
    CHECK_EQ_INT(dir_entries(dir), 1);

    /* hpfc_open maps it */
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    if (f) {
        hpfc_file_info fi;
        hpfc_file_get_info(f, &fi);
        CHECK(fi.crs_len == 9 && memcmp(fi.crs, "EPSG:4326", 9) == 0);
        CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL), HPFC_OK);
        CHECK_EQ_INT(probe_file(f, 1 << 20) & ~(OKB | BIT(HPFC_E_NO_PIXEL)), 0);
    }
    hpfc_close(f);

    /* a write that fails half-way (file size limit): the old file stays
     * byte-identical and no temporary is left */
    struct rlimit old_limit, small;
    if (getrlimit(RLIMIT_FSIZE, &old_limit) == 0) {
        void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
        small = old_limit;
        small.rlim_cur = 64;
        CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &small), 0);
        CHECK_EQ_INT(hpfc_tree_write_file(a, &plain, path, &d), HPFC_E_IO);
        CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
        signal(SIGXFSZ, old_handler);
        CHECK(file_equals(path, buf_b, size_b));
        CHECK_EQ_INT(dir_entries(dir), 1);
    }

    /* the target is a directory: the rename fails, nothing changes */
    CHECK_EQ_INT(mkdir(sub, 0755), 0);
    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, sub, &d), HPFC_E_IO);
    CHECK_EQ_INT(dir_entries(dir), 2);
    CHECK_EQ_INT(dir_entries(sub), 0);

    /* a directory we may not write to (meaningless for root) */
    if (geteuid() != 0) {
        CHECK_EQ_INT(chmod(dir, 0555), 0);
        CHECK_EQ_INT(hpfc_tree_write_file(a, &plain, path, &d), HPFC_E_IO);
        CHECK_EQ_INT(chmod(dir, 0755), 0);
        CHECK(file_equals(path, buf_b, size_b));
        CHECK_EQ_INT(dir_entries(dir), 2);
    }

    /* hpfc_open's failures */
    CHECK_EQ_INT(hpfc_open(bad, 0, &f), HPFC_E_IO);
    CHECK(f == NULL);
    CHECK_EQ_INT(hpfc_open(sub, 0, &f), HPFC_E_IO);
    char empty[256];
    snprintf(empty, sizeof empty, "%s/empty.hpfc", dir);
    FILE *e = fopen(empty, "wb");
    CHECK(e != NULL);
    if (e)
        fclose(e);
    CHECK_EQ_INT(hpfc_open(empty, 0, &f), HPFC_E_TRUNCATED);
    CHECK_EQ_INT(hpfc_open(NULL, 0, &f), HPFC_E_ARG);

    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, NULL, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_write_file(NULL, NULL, path, &d), HPFC_E_ARG);
    remove(empty);
    remove(path);
    rmdir(sub);
    CHECK_EQ_INT(rmdir(dir), 0); /* empty: nothing stray was left */
    hpfc_free(buf_a);
    hpfc_free(buf_b);
    hpfc_tree_free(a);
    hpfc_tree_free(b);
}

/* hpfc_file_write_fd of f, or hpfc_tree_write_fd of t when f is NULL,
 * into a file that held more bytes than it will (each 0xa5): exactly the
 * serialised bytes, the rest cut, the padding zeros. */
static void check_write_fd(const hpfc_file *f, const hpfc_tree *t, const hpfc_write_options *to,
                           const uint8_t *want, size_t want_size)
{
    FILE *tf = tmpfile();
    CHECK(tf != NULL);
    if (!tf)
        return;
    size_t old_size = want_size + 4096;
    uint8_t *junk = malloc(old_size);
    memset(junk, 0xa5, old_size);
    CHECK_EQ_INT(fwrite(junk, 1, old_size, tf), old_size);
    CHECK_EQ_INT(fflush(tf), 0);
    hpfc_diag d;
    hpfc_write_options in_layout = *to; /* the layout under test, as check_tree_serialize */
    if (in_layout.layout == HPFC_LAYOUT_DEFAULT)
        in_layout.layout = check_layout;
    if (f)
        CHECK_EQ_INT(hpfc_file_write_fd(f, to, fileno(tf), &d), HPFC_OK);
    else
        CHECK_EQ_INT(hpfc_tree_write_fd(t, &in_layout, fileno(tf), &d), HPFC_OK);
    struct stat st;
    CHECK_EQ_INT(fstat(fileno(tf), &st), 0);
    CHECK_EQ_INT((size_t)st.st_size, want_size);
    uint8_t *got = malloc(want_size + 1);
    CHECK_EQ_INT(pread(fileno(tf), got, want_size + 1, 0), (ssize_t)want_size);
    CHECK(memcmp(got, want, want_size) == 0);
    free(got);
    free(junk);
    fclose(tf);
}

/* What the descriptor writer refuses: no descriptor, one open for reading
 * only, a pipe (no size to set): HPFC_E_ARG, then HPFC_E_IO with the
 * system's reason. */
static void check_write_fd_refusals(const hpfc_file *f, const hpfc_tree *t, const char *path)
{
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_file_write_fd(f, NULL, -1, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_write_fd(NULL, NULL, 1, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_write_fd(t, NULL, -1, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_write_fd(NULL, NULL, 1, &d), HPFC_E_ARG);
    FILE *ro = fopen(path, "rb");
    CHECK(ro != NULL);
    if (ro) {
        CHECK_EQ_INT(hpfc_file_write_fd(f, NULL, fileno(ro), &d), HPFC_E_IO);
        CHECK(strstr(d.message, "cannot write") != NULL);
        CHECK_EQ_INT(hpfc_tree_write_fd(t, NULL, fileno(ro), &d), HPFC_E_IO);
        CHECK(strstr(d.message, "cannot write") != NULL);
        fclose(ro);
    }
    int p[2];
    CHECK_EQ_INT(pipe(p), 0);
    CHECK_EQ_INT(hpfc_file_write_fd(f, NULL, p[1], &d), HPFC_E_IO);
    CHECK_EQ_INT(hpfc_tree_write_fd(t, NULL, p[1], &d), HPFC_E_IO);
    close(p[0]), close(p[1]);
}

/* hpfc_file_serialize of a file serialised from tree t with `from` equals
 * hpfc_tree_serialize of t with `to`, byte for byte: the pools are copied
 * and the sections laid out as the tree writer lays them. */
static void check_reserialized(const hpfc_tree *t, const hpfc_write_options *from,
                               const hpfc_write_options *to, const char *path)
{
    uint8_t *src = NULL, *want = NULL, *got = NULL;
    size_t src_size = 0, want_size = 0, got_size = 0;
    hpfc_diag d;
    hpfc_file *f = NULL;
    CHECK_EQ_INT(check_tree_serialize(t, from, &src, &src_size, &d), HPFC_OK);
    CHECK_EQ_INT(check_tree_serialize(t, to, &want, &want_size, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(src, src_size, 0, &f), HPFC_OK);
    if (f) {
        CHECK_EQ_INT(hpfc_file_serialize(f, to, &got, &got_size, &d), HPFC_OK);
        CHECK(got && got_size == want_size && memcmp(got, want, want_size) == 0);
        CHECK_EQ_INT(hpfc_file_write_file(f, to, path, &d), HPFC_OK);
        CHECK(file_equals(path, want, want_size));
        check_write_fd(f, NULL, to, want, want_size);
    }
    check_write_fd(NULL, t, to, want, want_size);
    hpfc_close(f);
    hpfc_free(src), hpfc_free(want), hpfc_free(got);
}

static void test_file_serialize(void)
{
    char dir[] = "/tmp/hpfc-test-write-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    hpfc_tree *t = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!t)
        return;
    size_t size;
    uint8_t *plain = serialize(t, NULL, &size);
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_open_memory(plain, size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    feat_fixture x;
    feat_fixture_make(&x, (uint32_t)hpfc_faces_face_count(fc));
    hpfc_faces_free(fc);
    const hpfc_write_options opts[4] = {
        {.crs = NULL},
        {.crs = "EPSG:4326"},
        {.features = &x.t},
        {.crs = "+proj=lcc +lat_1=33", .features = &x.t}};
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            check_reserialized(t, &opts[a], &opts[b], path);
    /* opts NULL: no optional section */
    uint8_t *got = NULL;
    size_t got_size = 0;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_file_serialize(f, NULL, &got, &got_size, &d), HPFC_OK);
    CHECK(got && got_size == size && memcmp(got, plain, size) == 0);
    hpfc_free(got);
    CHECK_EQ_INT(hpfc_file_serialize(NULL, NULL, &got, &got_size, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_serialize(f, NULL, NULL, &got_size, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_write_file(f, NULL, NULL, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_write_file(NULL, NULL, path, &d), HPFC_E_ARG);
    check_write_fd_refusals(f, t, path);
    hpfc_close(f);
    hpfc_free(plain);
    free(x.start), free(x.link);
    hpfc_tree_free(t);
    remove(path);
    rmdir(dir);
}

int main(void)
{
    check_use_test_layout();
    test_write_file();
    test_file_serialize();
    return check_report("test_write");
}
