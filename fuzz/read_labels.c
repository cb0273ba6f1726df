/*
 * read_labels: the LABL section (spec/hpfc-format.md §6.5) on an opened
 * file, driven by the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated sections and pools reach the
 * label code. Without commands: every leaf (at most 512) through every
 * label accessor, 16 located points, then hpfc_faces_build (and again on
 * 3 threads) and hpfc_labels_verify. With commands: the accessors on leaves, on darts
 * naming any crossing and on pixel stacks with input-chosen depths, image
 * offsets and indices (untrusted, as a caller's). At most FUZZ_STEPS calls.
 *
 * Oracle: known statuses only; every face id below the section's face
 * count and every edge id below its edge count; a leaf number below its
 * level's word pixels; a leaf's face count is its regions (1 private,
 * else crossings - components + 1) and the count query agrees with the
 * listing; a dart's face is the face of the stretch after its crossing;
 * indices one past the end are HPFC_E_ARG; when hpfc_labels_verify accepts
 * the section, every leaf's number is the pool walk's and every stretch's
 * face is hpfc_faces_build's; the faces numbered on 3 threads fail as
 * one thread's do, at the same leaf, or are the same faces.
 */
#include "faces.h"
#include "file.h"
#include "input.h"
#include "labels.h"

#define FUZZ_STEPS 2000
#define FUZZ_LEAVES 512

typedef struct lab {
    const hpfc_file *f;
    hpfc_file_info info;
    hpfc_labels_info li;
    long steps;
    char word[4096];
    uint64_t faces[1024];
} lab;

static bool spend(lab *z)
{
    return z->steps-- > 0;
}

static void check_status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st));
}

/* Crossings and components of a leaf's word, when it decodes and parses. */
static bool word_shape(lab *z, const hpfc_pixel *px, uint32_t *n, uint32_t *regions)
{
    size_t len = 0;
    if (hpfc_pixel_word(z->f, px, z->word, sizeof z->word, &len) != HPFC_OK)
        return false;
    labels_word w;
    int st = labels_word_parse(&w, z->word, len);
    *n = w.n;
    *regions = w.regions;
    labels_word_free(&w);
    return st == HPFC_OK;
}

/* Every accessor on one pixel (a leaf or not). */
static void probe_pixel(lab *z, const hpfc_pixel *px, uint32_t extra_crossing)
{
    uint64_t number = 0, face = 0, edge = 0, again = 0;
    int st = hpfc_leaf_number(z->f, px, &number);
    check_status(st);
    if (!st) {
        hpfc_level_info lv;
        FUZZ_CHECK(hpfc_file_get_level(z->f, px->depth, &lv) == HPFC_OK);
        FUZZ_CHECK(number < lv.word_pixels);
    }
    size_t count = 0, count2 = 0;
    st = hpfc_label_leaf_faces(z->f, px, NULL, 0, &count);
    check_status(st);
    uint32_t n = 0, regions = 0;
    bool shaped = st == HPFC_OK && word_shape(z, px, &n, &regions);
    if (shaped)
        FUZZ_CHECK(count == regions);
    if (st == HPFC_OK && count <= 1024) {
        int s2 = hpfc_label_leaf_faces(z->f, px, z->faces, count, &count2);
        check_status(s2);
        FUZZ_CHECK(s2 != HPFC_OK || count2 == count);
        for (size_t k = 0; s2 == HPFC_OK && k < count2; k++)
            FUZZ_CHECK(z->faces[k] < z->li.faces);
        if (count > 0)
            FUZZ_CHECK(hpfc_label_leaf_faces(z->f, px, z->faces, count - 1, &count2) ==
                       HPFC_E_BUFFER_SMALL);
    }
    if (!shaped)
        return;
    uint32_t limit = n < 64 ? n : 64;
    for (uint32_t k = 0; k < limit && spend(z); k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        int s1 = hpfc_label_dart_face(z->f, &d, &face);
        int s2 = hpfc_label_stretch_face(z->f, px, (k + 1) % n, &again);
        check_status(s1);
        FUZZ_CHECK(s1 == s2);
        if (!s1)
            FUZZ_CHECK(face == again && face < z->li.faces);
        s1 = hpfc_label_crossing_edge(z->f, px, k, &edge);
        check_status(s1);
        FUZZ_CHECK(s1 != HPFC_OK || edge < z->li.edges);
        s2 = hpfc_label_dart_edge(z->f, &d, &again);
        FUZZ_CHECK(s1 == s2 && (s1 || again == edge));
    }
    uint32_t stretches = n ? n : 1;
    FUZZ_CHECK(hpfc_label_stretch_face(z->f, px, stretches, &face) == HPFC_E_ARG);
    FUZZ_CHECK(hpfc_label_crossing_edge(z->f, px, n, &edge) == HPFC_E_ARG);
    hpfc_dart past = {.pixel = *px, .crossing = n + extra_crossing};
    FUZZ_CHECK(hpfc_label_dart_face(z->f, &past, &face) == HPFC_E_ARG);
}

/* The faces numbered again on 3 threads (in runs of 3 leaves in fuzzing
 * builds, faces.c): the status of one thread's numbering `st`, from the
 * same leaf's failure `fail`, and when it numbers, the same faces. */
static void numbered_alike(lab *z, int st, uint64_t fail, const hpfc_faces *fc)
{
    hpfc_faces *many = NULL;
    uint64_t fail3 = 0;
    int st3 = faces_build_width(z->f, FACES_NARROW_NODES, 3, 0, &fail3, &many);
    FUZZ_CHECK(st3 == st && fail3 == fail);
    if (!st && !st3) {
        FUZZ_CHECK(hpfc_faces_face_count(many) == hpfc_faces_face_count(fc));
        hpfc_pixel px;
        long leaves = 0;
        for (int s = hpfc_leaf_first(z->f, &px); !s && leaves < FUZZ_LEAVES;
             s = hpfc_leaf_next(z->f, &px), leaves++) {
            hpfc_dart d = {.pixel = px};
            for (d.crossing = 0; d.crossing < 64; d.crossing++) {
                uint64_t a = 0, b = 0;
                int sa = hpfc_faces_dart_face(fc, &d, &a), sb = hpfc_faces_dart_face(many, &d, &b);
                FUZZ_CHECK(sa == sb && a == b);
                if (sa)
                    break;
            }
        }
    }
    hpfc_faces_free(many);
}

/* hpfc_labels_verify; when it accepts, the labels are the map's. */
static void verify(lab *z)
{
    hpfc_faces *fc = NULL;
    uint64_t fail = 0;
    int st = faces_build_width(z->f, FACES_NARROW_NODES, 1, 0, &fail, &fc);
    check_status(st);
    numbered_alike(z, st, fail, fc);
    if (st)
        return;
    hpfc_labels_report rep;
    st = hpfc_labels_verify(z->f, fc, &rep);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT || st == HPFC_E_NOMEM);
    FUZZ_CHECK(st != HPFC_E_CORRUPT || rep.message[0]);
    if (st == HPFC_OK) {
        hpfc_file_info fi;
        hpfc_file_get_info(z->f, &fi);
        int compact = (fi.incompat_flags & 1) != 0; /* spec §4.3 */
        hpfc_pixel px;
        long leaves = 0;
        for (int s = hpfc_leaf_first(z->f, &px); !s && leaves < FUZZ_LEAVES;
             s = hpfc_leaf_next(z->f, &px), leaves++) {
            uint64_t fast = 0, walk = 0, want = 0, got = 0;
            FUZZ_CHECK(hpfc_leaf_number(z->f, &px, &fast) == HPFC_OK);
            if (!compact) { /* the walk reads the paper layout's pools */
                FUZZ_CHECK(labels_rank_by_walk(z->f, &px, &walk) == HPFC_OK);
                FUZZ_CHECK(fast == walk);
            }
            int is_private = 0;
            FUZZ_CHECK(hpfc_pixel_is_private(z->f, &px, &is_private) == HPFC_OK);
            if (is_private) {
                FUZZ_CHECK(hpfc_faces_pixel_face(fc, &px, &want) == HPFC_OK);
                FUZZ_CHECK(hpfc_label_stretch_face(z->f, &px, 0, &got) == HPFC_OK);
                FUZZ_CHECK(got == want);
            }
        }
    }
    hpfc_faces_free(fc);
}

static void explore(lab *z)
{
    hpfc_pixel px;
    long leaves = 0;
    int st;
    for (st = hpfc_leaf_first(z->f, &px); !st && leaves < FUZZ_LEAVES && spend(z);
         st = hpfc_leaf_next(z->f, &px), leaves++)
        probe_pixel(z, &px, 0);
    check_status(st);
    for (int k = 0; k < 16 && spend(z); k++) {
        int64_t x = z->info.x0 + (int64_t)((uint64_t)z->info.width * (uint64_t)(2 * k + 1) / 32);
        int64_t y = z->info.y0 + (int64_t)((uint64_t)z->info.height * (uint64_t)(31 - 2 * k) / 32);
        if (hpfc_locate(z->f, x, y, &px) == HPFC_OK)
            probe_pixel(z, &px, 7);
    }
    if (file_total_leaves(z->f) <= 4096)
        verify(z);
}

/* A pixel stack from the input: depth, then per level an image offset
 * (0: the parent's child as the pools say), i and j. */
static void input_pixel(lab *z, fuzz_bytes *in, hpfc_pixel *px)
{
    memset(px, 0, sizeof *px);
    px->depth = fuzz_u8(in) % (z->info.levels + 1);
    if (px->depth >= HPFC_MAX_LEVELS)
        px->depth = HPFC_MAX_LEVELS - 1;
    for (uint32_t l = 0; l <= px->depth; l++) {
        uint8_t how = fuzz_u8(in);
        px->path[l].i = fuzz_u16(in);
        px->path[l].j = fuzz_u16(in);
        if (how & 1)
            px->path[l].image = fuzz_u32(in);
        else if (l > 0) {
            hpfc_pixel parent = *px, child;
            parent.depth = l - 1;
            if (hpfc_pixel_child(z->f, &parent, px->path[l].i, px->path[l].j, &child) == HPFC_OK)
                px->path[l].image = child.path[l].image;
        }
    }
}

static void run_commands(lab *z, fuzz_bytes *in)
{
    hpfc_pixel px;
    memset(&px, 0, sizeof px);
    while (!fuzz_empty(in) && spend(z)) {
        switch (fuzz_u8(in) % 4) {
        case 0: /* a located point */
            if (hpfc_locate(z->f, z->info.x0 + (int64_t)(fuzz_u32(in) % (uint64_t)z->info.width),
                            z->info.y0 + (int64_t)(fuzz_u32(in) % (uint64_t)z->info.height),
                            &px) == HPFC_OK)
                probe_pixel(z, &px, fuzz_u8(in));
            break;
        case 1: /* a caller's pixel stack */
            input_pixel(z, in, &px);
            probe_pixel(z, &px, fuzz_u8(in));
            break;
        case 2: { /* a dart naming any crossing of the current pixel */
            hpfc_dart d = {.pixel = px, .crossing = fuzz_u32(in)};
            uint64_t v;
            check_status(hpfc_label_dart_face(z->f, &d, &v));
            check_status(hpfc_label_dart_edge(z->f, &d, &v));
            check_status(hpfc_label_stretch_face(z->f, &px, d.crossing, &v));
            break;
        }
        default: /* the next leaf */
            if (hpfc_leaf_next(z->f, &px) != HPFC_OK)
                check_status(hpfc_leaf_first(z->f, &px));
            break;
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *file;
    size_t file_size;
    fuzz_bytes cmds;
    if (!fuzz_split_file(data, size, &file, &file_size, &cmds))
        return 0;
    hpfc_file *f = NULL;
    if (hpfc_open_memory(file, file_size, HPFC_OPEN_SKIP_CHECKSUM, &f) == HPFC_OK) {
        lab z = {.f = f, .steps = FUZZ_STEPS};
        hpfc_file_get_info(f, &z.info);
        int st = hpfc_file_get_labels(f, &z.li);
        FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
        if (st == HPFC_OK) {
            FUZZ_CHECK(z.li.faces > 0 && z.li.edges > 0);
            if (fuzz_empty(&cmds))
                explore(&z);
            else
                run_commands(&z, &cmds);
        } else {
            hpfc_pixel px;
            uint64_t v;
            size_t c;
            if (hpfc_leaf_first(f, &px) == HPFC_OK)
                FUZZ_CHECK(hpfc_label_leaf_faces(f, &px, NULL, 0, &c) == HPFC_E_NO_SECTION &&
                           hpfc_label_crossing_edge(f, &px, 0, &v) == HPFC_E_NO_SECTION);
        }
        hpfc_close(f);
    }
    free(file);
    return 0;
}
