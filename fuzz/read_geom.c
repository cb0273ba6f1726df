/*
 * read_geom: the GEOM section (spec/hpfc-format.md §6.6) on an opened file,
 * driven by the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated sections and pools reach the
 * geometry code. Without commands: hpfc_geometry_bounds (on a small map
 * whose every point reads, equal to the box of them all), the first 512
 * vertices and edges
 * through every accessor (every point of an edge, at most 64, and one
 * past), every crossing of the first 512 leaves, 16 located points, then
 * (files of at most 4096 leaves) hpfc_geometry_verify. With commands: any
 * vertex, edge, point and crossing ids (64-bit), located points, leaf
 * iteration. At most FUZZ_STEPS calls.
 *
 * Oracle: known statuses only; ids at or past the counts are HPFC_E_ARG;
 * every coordinate returned lies in the domain; an edge's ends are below
 * the vertex count, its point count at least 2 (4 for a loop), its first
 * and last points its ends' coordinates; faces below LABL's face count;
 * a crossing's segment below its edge's point count - 1; the same call
 * twice gives the same answer; verify gives OK, CORRUPT with a message,
 * or NOMEM, and when it accepts, every edge's points are distinct from
 * their neighbours and every crossing reads.
 */
#include "input.h"

#define FUZZ_STEPS 4000
#define FUZZ_ITEMS 512

typedef struct geo {
    const hpfc_file *f;
    hpfc_file_info info;
    hpfc_geometry_info gi;
    int has_labels;
    hpfc_labels_info li;
    long steps;
} geo;

static bool spend(geo *z)
{
    return z->steps-- > 0;
}

static void check_status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st));
}

static bool in_domain(const geo *z, int64_t x, int64_t y)
{
    return x >= z->info.x0 && x - z->info.x0 < z->info.width && y >= z->info.y0 &&
           y - z->info.y0 < z->info.height;
}

static void probe_vertex(geo *z, uint64_t v)
{
    int64_t x = 0, y = 0, x2 = 1, y2 = 1;
    int st = hpfc_geometry_vertex(z->f, v, &x, &y);
    check_status(st);
    FUZZ_CHECK((st == HPFC_E_ARG) == (v >= z->gi.vertices));
    if (st == HPFC_OK) {
        FUZZ_CHECK(in_domain(z, x, y));
        FUZZ_CHECK(hpfc_geometry_vertex(z->f, v, &x2, &y2) == HPFC_OK && x2 == x && y2 == y);
    }
}

static void probe_edge(geo *z, uint64_t e)
{
    uint64_t u = 0, v = 0, n = 0, left = 0, right = 0;
    int st = hpfc_geometry_edge(z->f, e, &u, &v, &n);
    check_status(st);
    FUZZ_CHECK((st == HPFC_E_ARG) == (e >= z->gi.edges));
    int sf = hpfc_geometry_edge_faces(z->f, e, &left, &right);
    FUZZ_CHECK(sf == HPFC_E_NO_SECTION || fuzz_known_status(sf));
    if (!z->has_labels)
        FUZZ_CHECK(sf == HPFC_E_NO_SECTION);
    else if (sf == HPFC_OK)
        FUZZ_CHECK(left < z->li.faces && right < z->li.faces);
    if (st != HPFC_OK)
        return;
    FUZZ_CHECK(u < z->gi.vertices && v < z->gi.vertices && n >= 2 && n - 2 <= z->gi.points);
    FUZZ_CHECK(u != v || n >= 4);
    uint64_t limit = n < 64 ? n : 64;
    for (uint64_t k = 0; k < limit && spend(z); k++) {
        int64_t x = 0, y = 0, vx, vy;
        int sp = hpfc_geometry_edge_point(z->f, e, k, &x, &y);
        check_status(sp);
        FUZZ_CHECK(sp != HPFC_E_ARG);
        if (sp != HPFC_OK)
            continue;
        FUZZ_CHECK(in_domain(z, x, y));
        if (k == 0 || k == n - 1) { /* the ends are the vertices' points */
            FUZZ_CHECK(hpfc_geometry_vertex(z->f, k ? v : u, &vx, &vy) == HPFC_OK);
            FUZZ_CHECK(vx == x && vy == y);
        }
    }
    int64_t x, y;
    FUZZ_CHECK(hpfc_geometry_edge_point(z->f, e, n, &x, &y) == HPFC_E_ARG);
}

/* Every crossing of a leaf (at most 64) and one past. */
static void probe_leaf(geo *z, const hpfc_pixel *px, uint32_t extra)
{
    size_t len = 0;
    if (hpfc_pixel_word(z->f, px, NULL, 0, &len) != HPFC_OK || len < 4)
        return;
    uint32_t n = (uint32_t)(len - 4), limit = n < 64 ? n : 64;
    for (uint32_t k = 0; k < limit && spend(z); k++) {
        uint64_t seg = 0, again = 1, edge, u, v, count;
        int st = hpfc_geometry_crossing_segment(z->f, px, k, &seg);
        check_status(st);
        FUZZ_CHECK(st != HPFC_E_ARG && st != HPFC_E_NO_SECTION);
        if (st != HPFC_OK)
            continue;
        FUZZ_CHECK(hpfc_geometry_crossing_segment(z->f, px, k, &again) == HPFC_OK && again == seg);
        if (z->has_labels && hpfc_label_crossing_edge(z->f, px, k, &edge) == HPFC_OK &&
            hpfc_geometry_edge(z->f, edge, &u, &v, &count) == HPFC_OK)
            FUZZ_CHECK(seg + 1 < count);
    }
    uint64_t seg;
    int st = hpfc_geometry_crossing_segment(z->f, px, n + extra, &seg);
    check_status(st);
    FUZZ_CHECK(st != HPFC_OK);
}

static void verify(geo *z)
{
    hpfc_geometry_report rep;
    int st = hpfc_geometry_verify(z->f, &rep);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT || st == HPFC_E_NOMEM);
    FUZZ_CHECK(st != HPFC_E_CORRUPT || rep.message[0]);
    if (st != HPFC_OK)
        return;
    FUZZ_CHECK(rep.vertices_checked == z->gi.vertices);
    /* accepted: every point reads and no segment has zero length */
    for (uint64_t e = 0; e < z->gi.edges && e < FUZZ_ITEMS; e++) {
        uint64_t u, v, n;
        FUZZ_CHECK(hpfc_geometry_edge(z->f, e, &u, &v, &n) == HPFC_OK);
        int64_t px = 0, py = 0;
        for (uint64_t k = 0; k < n && k < 64; k++) {
            int64_t x, y;
            FUZZ_CHECK(hpfc_geometry_edge_point(z->f, e, k, &x, &y) == HPFC_OK);
            FUZZ_CHECK(k == 0 || x != px || y != py);
            px = x, py = y;
        }
    }
}

/* hpfc_geometry_bounds: known statuses; an answer inside the domain, and,
 * on a small map whose every vertex and edge point reads, the box of them
 * all (it reads only blocks whose bases and widths allow a wider box, so
 * mutated directories test its pruning against every value). */
static void probe_bounds(geo *z)
{
    int64_t box[4];
    int st = hpfc_geometry_bounds(z->f, box);
    check_status(st);
    FUZZ_CHECK(st != HPFC_E_ARG && st != HPFC_E_NO_SECTION);
    if (st != HPFC_OK)
        return;
    FUZZ_CHECK(in_domain(z, box[0], box[1]) && in_domain(z, box[2], box[3]));
    FUZZ_CHECK(box[0] <= box[2] && box[1] <= box[3]);
    if (z->gi.vertices + z->gi.points > 65536)
        return;
    int64_t want[4] = {INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN};
    uint64_t seen = 0;
    for (uint64_t v = 0; v < z->gi.vertices; v++) {
        int64_t x, y;
        if (hpfc_geometry_vertex(z->f, v, &x, &y) != HPFC_OK)
            return;
        want[0] = x < want[0] ? x : want[0], want[1] = y < want[1] ? y : want[1];
        want[2] = x > want[2] ? x : want[2], want[3] = y > want[3] ? y : want[3];
    }
    for (uint64_t e = 0; e < z->gi.edges; e++) {
        uint64_t u, v, n;
        if (hpfc_geometry_edge(z->f, e, &u, &v, &n) != HPFC_OK)
            return;
        for (uint64_t k = 1; k + 1 < n; k++, seen++) {
            int64_t x, y;
            if (hpfc_geometry_edge_point(z->f, e, k, &x, &y) != HPFC_OK)
                return;
            want[0] = x < want[0] ? x : want[0], want[1] = y < want[1] ? y : want[1];
            want[2] = x > want[2] ? x : want[2], want[3] = y > want[3] ? y : want[3];
        }
    }
    /* every shape point belongs to one edge: reached them all, the boxes agree */
    if (seen == z->gi.points)
        FUZZ_CHECK(box[0] == want[0] && box[1] == want[1] && box[2] == want[2] &&
                   box[3] == want[3]);
}

static void explore(geo *z)
{
    probe_bounds(z);
    for (uint64_t v = 0; v < z->gi.vertices && v < FUZZ_ITEMS && spend(z); v++)
        probe_vertex(z, v);
    probe_vertex(z, z->gi.vertices);
    for (uint64_t e = 0; e < z->gi.edges && e < FUZZ_ITEMS && spend(z); e++)
        probe_edge(z, e);
    probe_edge(z, z->gi.edges);
    hpfc_pixel px;
    long leaves = 0;
    int st;
    for (st = hpfc_leaf_first(z->f, &px); !st && leaves < FUZZ_ITEMS && spend(z);
         st = hpfc_leaf_next(z->f, &px), leaves++)
        probe_leaf(z, &px, 0);
    check_status(st);
    for (int k = 0; k < 16 && spend(z); k++) {
        int64_t x = z->info.x0 + (int64_t)((uint64_t)z->info.width * (uint64_t)(2 * k + 1) / 32);
        int64_t y = z->info.y0 + (int64_t)((uint64_t)z->info.height * (uint64_t)(31 - 2 * k) / 32);
        if (hpfc_locate(z->f, x, y, &px) == HPFC_OK)
            probe_leaf(z, &px, 5);
    }
    hpfc_level_info lv;
    uint64_t leaves_all = 0;
    for (uint32_t l = 0; l < z->info.levels && hpfc_file_get_level(z->f, l, &lv) == HPFC_OK; l++)
        leaves_all += lv.word_pixels;
    if (leaves_all <= 4096 && z->gi.vertices + z->gi.points <= 65536)
        verify(z);
}

static void run_commands(geo *z, fuzz_bytes *in)
{
    hpfc_pixel px;
    memset(&px, 0, sizeof px);
    bool have_leaf = false;
    while (!fuzz_empty(in) && spend(z)) {
        switch (fuzz_u8(in) % 5) {
        case 0:
            probe_vertex(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in));
            break;
        case 1:
            probe_edge(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in));
            break;
        case 2: { /* any point of any edge */
            int64_t x, y;
            uint64_t e = fuzz_u16(in), k = fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in);
            int st = hpfc_geometry_edge_point(z->f, e, k, &x, &y);
            check_status(st);
            FUZZ_CHECK(st != HPFC_OK || in_domain(z, x, y));
            break;
        }
        case 3: /* a located point */
            if (hpfc_locate(z->f, z->info.x0 + (int64_t)(fuzz_u32(in) % (uint64_t)z->info.width),
                            z->info.y0 + (int64_t)(fuzz_u32(in) % (uint64_t)z->info.height),
                            &px) == HPFC_OK) {
                have_leaf = true;
                probe_leaf(z, &px, fuzz_u8(in));
            }
            break;
        default: /* the next leaf, and any crossing of it */
            if (!have_leaf || hpfc_leaf_next(z->f, &px) != HPFC_OK)
                have_leaf = hpfc_leaf_first(z->f, &px) == HPFC_OK;
            if (have_leaf) {
                uint64_t seg;
                check_status(hpfc_geometry_crossing_segment(z->f, &px, fuzz_u32(in), &seg));
            }
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
        geo z = {.f = f, .steps = FUZZ_STEPS};
        hpfc_file_get_info(f, &z.info);
        z.has_labels = hpfc_file_get_labels(f, &z.li) == HPFC_OK;
        int st = hpfc_file_get_geometry(f, &z.gi);
        FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
        if (st == HPFC_OK) {
            FUZZ_CHECK(z.gi.vertices > 0 && z.gi.edges > 0);
            FUZZ_CHECK(!z.has_labels || z.li.edges == z.gi.edges);
            if (fuzz_empty(&cmds))
                explore(&z);
            else
                run_commands(&z, &cmds);
        } else {
            int64_t x, y;
            uint64_t a, b, c;
            hpfc_geometry_report rep;
            FUZZ_CHECK(hpfc_geometry_vertex(f, 0, &x, &y) == HPFC_E_NO_SECTION);
            FUZZ_CHECK(hpfc_geometry_edge(f, 0, &a, &b, &c) == HPFC_E_NO_SECTION);
            FUZZ_CHECK(hpfc_geometry_verify(f, &rep) == HPFC_E_NO_SECTION);
            int64_t box[4];
            FUZZ_CHECK(hpfc_geometry_bounds(f, box) == HPFC_E_NO_SECTION);
        }
        hpfc_close(f);
    }
    free(file);
    return 0;
}
