/*
 * The reader alone (libhpfcreader: libhpfcfile's groups common to verify,
 * linked here without libm and without the builder or writer): what an
 * embedder that only maps files links. On every valid fixture of
 * tests/data/valid: open with checksums, every leaf in order with its word
 * (a word has four '+'), every pixel found again by locating a point inside
 * it, the faces numbered (a private leaf's face below the count), the
 * labels and geometry verified where the file has them, and every face's
 * and feature's rings (closed, at least four points). A call this program
 * makes that the reader does not hold fails the link; a library it needs
 * beyond libc fails it too (tests/lib/check_reader.py checks the archive).
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"

static void check_leaves(const hpfc_file *f, const hpfc_faces *faces, uint64_t *leaves)
{
    hpfc_pixel px;
    char word[4096];
    int st = hpfc_leaf_first(f, &px);
    for (; st == HPFC_OK; st = hpfc_leaf_next(f, &px)) {
        size_t len, plus = 0;
        CHECK_EQ_INT(hpfc_pixel_word(f, &px, word, sizeof word, &len), HPFC_OK);
        for (size_t k = 0; k < len && k < sizeof word; k++)
            plus += word[k] == '+';
        CHECK_EQ_INT(plus, 4);
        int64_t x0, y0, x1, y1;
        CHECK_EQ_INT(hpfc_pixel_bounds(f, &px, &x0, &y0, &x1, &y1), HPFC_OK);
        hpfc_pixel at;
        CHECK_EQ_INT(hpfc_locate(f, x0 + (x1 - x0) / 2, y0 + (y1 - y0) / 2, &at), HPFC_OK);
        CHECK(at.depth == px.depth &&
              memcmp(at.path, px.path, (px.depth + 1) * sizeof px.path[0]) == 0);
        int is_private = 0;
        CHECK_EQ_INT(hpfc_pixel_is_private(f, &px, &is_private), HPFC_OK);
        CHECK_EQ_INT(is_private, len == 4);
        if (is_private) {
            uint64_t face;
            CHECK_EQ_INT(hpfc_faces_pixel_face(faces, &px, &face), HPFC_OK);
            CHECK(face < hpfc_faces_face_count(faces));
        }
        ++*leaves;
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
}

static void check_rings(const hpfc_polygons *p)
{
    for (size_t r = 0; r < p->ring_count; r++) {
        size_t a = p->ring_point[r], b = p->ring_point[r + 1];
        CHECK(b - a >= 4);
        CHECK(p->xy[2 * a] == p->xy[2 * b - 2] && p->xy[2 * a + 1] == p->xy[2 * b - 1]);
    }
}

static void check_shapes(const hpfc_file *f, const hpfc_faces *faces)
{
    hpfc_shapes *s;
    if (hpfc_shapes_create(f, &s) != HPFC_OK)
        return; /* no GEOM: nothing to draw */
    CHECK_EQ_INT(hpfc_shapes_face_count(s), hpfc_faces_face_count(faces));
    hpfc_polygons p;
    for (uint64_t face = 0; face < hpfc_shapes_face_count(s); face++) {
        CHECK_EQ_INT(hpfc_shapes_face_polygons(s, face, &p), HPFC_OK);
        check_rings(&p);
    }
    hpfc_features_info fi;
    if (hpfc_file_get_features(f, &fi) == HPFC_OK)
        for (uint32_t k = 0; k < fi.features; k++) {
            CHECK_EQ_INT(hpfc_shapes_feature_polygons(s, k, &p), HPFC_OK);
            check_rings(&p);
        }
    hpfc_shapes_free(s);
}

static void check_file(const char *path, uint64_t *files, uint64_t *leaves)
{
    hpfc_file *f;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    if (!f)
        return;
    CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL), HPFC_OK);
    hpfc_faces *faces;
    CHECK_EQ_INT(hpfc_faces_build(f, &faces), HPFC_OK);
    if (faces) {
        check_leaves(f, faces, leaves);
        hpfc_labels_report lr;
        int st = hpfc_labels_verify(f, faces, &lr);
        CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
        hpfc_geometry_report gr;
        st = hpfc_geometry_verify(f, &gr);
        CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
        check_shapes(f, faces);
        hpfc_faces_free(faces);
    }
    hpfc_close(f);
    ++*files;
}

int main(void)
{
    const char *data = getenv("HPFC_TEST_DATA");
    char dir[4096], path[8192];
    snprintf(dir, sizeof dir, "%s/valid", data ? data : "tests/data");
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    uint64_t files = 0, leaves = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
        size_t n = strlen(e->d_name);
        if (n < 5 || strcmp(e->d_name + n - 5, ".hpfc") != 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        check_file(path, &files, &leaves);
    }
    if (d)
        closedir(d);
    CHECK(files >= 5 && leaves >= 100);
    printf("%llu files, %llu leaves\n", (unsigned long long)files, (unsigned long long)leaves);
    return check_report("reader_only");
}
