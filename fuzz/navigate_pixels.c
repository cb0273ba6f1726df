/*
 * navigate_pixels: navigation on an opened file, driven by the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h). The file
 * is opened with HPFC_OPEN_SKIP_CHECKSUM so mutated pools reach the pixel
 * code. Without commands the harness walks the leaves in order and, from
 * each, decodes its word and moves in the four directions; with commands,
 * each command byte picks one navigation call (root, child, parent, move,
 * locate, word decode, type, bounds, leaf iteration, or a pixel stack with
 * an input-chosen image offset, which the API must treat as untrusted).
 * At most FUZZ_STEPS calls per input.
 *
 * Oracle (holds for any pool contents, since pixel geometry follows the
 * pixel stack and not the pool): statuses are known codes; a child lies in
 * its parent; a located leaf holds the point; a move lands on a word pixel
 * across the road of the direction taken, sharing part of it, either
 * spanning the side (no deeper) or at its clockwise-first end (deeper);
 * decoded words have four '+', the last one last, and only the seven
 * symbols; a word's length is the same whether it is asked with a buffer
 * or not; a word pixel is private iff its word is "++++".
 */
#include "input.h"

#define FUZZ_STEPS 2000

typedef struct nav {
    const hpfc_file *f;
    hpfc_file_info info;
    long steps;
    char word[4096];
} nav;

static bool spend(nav *n)
{
    return n->steps-- > 0;
}

static void check_status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st));
}

typedef struct box {
    int64_t x0, y0, x1, y1;
} box;

static int bounds(nav *n, const hpfc_pixel *px, box *b)
{
    int st = hpfc_pixel_bounds(n->f, px, &b->x0, &b->y0, &b->x1, &b->y1);
    check_status(st);
    if (!st) {
        FUZZ_CHECK(b->x0 < b->x1 && b->y0 < b->y1);
        FUZZ_CHECK(b->x0 >= n->info.x0 && b->x1 <= n->info.x0 + n->info.width);
        FUZZ_CHECK(b->y0 >= n->info.y0 && b->y1 <= n->info.y0 + n->info.height);
    }
    return st;
}

/* Word, private flag and type of px, checked against each other. */
static void decode(nav *n, const hpfc_pixel *px, size_t cap)
{
    int type, is_private;
    int st = hpfc_pixel_type(n->f, px, &type);
    check_status(st);
    int st_private = hpfc_pixel_is_private(n->f, px, &is_private);
    check_status(st_private);
    size_t len = 0, len2 = 0;
    int st_len = hpfc_pixel_word(n->f, px, NULL, 0, &len);
    check_status(st_len);
    if (cap > sizeof n->word)
        cap = sizeof n->word;
    int st_word = hpfc_pixel_word(n->f, px, n->word, cap, &len2);
    check_status(st_word);
    if (st)
        return;
    if (type == HPFC_PIXEL_REFINED) {
        FUZZ_CHECK(st_len == HPFC_E_ARG && st_word == HPFC_E_ARG);
        FUZZ_CHECK(st_private == HPFC_OK && !is_private);
        return;
    }
    FUZZ_CHECK(type == HPFC_PIXEL_WORD);
    if (st_len) {
        FUZZ_CHECK(st_len == HPFC_E_CORRUPT && st_word == HPFC_E_CORRUPT);
        return;
    }
    FUZZ_CHECK(len2 == len && len >= 4);
    if (len > cap) {
        FUZZ_CHECK(st_word == HPFC_E_BUFFER_SMALL);
        return;
    }
    FUZZ_CHECK(st_word == HPFC_OK);
    int plus = 0;
    for (size_t k = 0; k < len; k++) {
        FUZZ_CHECK(strchr("+=[]()Y", n->word[k]) != NULL && n->word[k] != '\0');
        plus += n->word[k] == '+';
    }
    FUZZ_CHECK(plus == 4 && n->word[len - 1] == '+');
    FUZZ_CHECK(st_private == HPFC_OK && is_private == (len == 4));
}

static bool overlap(int64_t a0, int64_t a1, int64_t b0, int64_t b1)
{
    return a0 < b1 && b0 < a1;
}

static void move(nav *n, const hpfc_pixel *px, int dir)
{
    hpfc_pixel out;
    int st = hpfc_pixel_move(n->f, px, dir, &out);
    check_status(st);
    if (dir < HPFC_WEST || dir > HPFC_SOUTH) {
        FUZZ_CHECK(st == HPFC_E_ARG);
        return;
    }
    box p, q;
    if (st || bounds(n, px, &p) || bounds(n, &out, &q))
        return;
    int type;
    FUZZ_CHECK(hpfc_pixel_type(n->f, &out, &type) == HPFC_OK && type == HPFC_PIXEL_WORD);
    bool deeper = out.depth > px->depth;
    switch (dir) {
    case HPFC_WEST:
        FUZZ_CHECK(q.x1 == p.x0 && overlap(p.y0, p.y1, q.y0, q.y1));
        FUZZ_CHECK(deeper ? q.y1 == p.y1 && q.y0 >= p.y0 : q.y0 <= p.y0 && q.y1 >= p.y1);
        break;
    case HPFC_EAST:
        FUZZ_CHECK(q.x0 == p.x1 && overlap(p.y0, p.y1, q.y0, q.y1));
        FUZZ_CHECK(deeper ? q.y0 == p.y0 && q.y1 <= p.y1 : q.y0 <= p.y0 && q.y1 >= p.y1);
        break;
    case HPFC_NORTH:
        FUZZ_CHECK(q.y0 == p.y1 && overlap(p.x0, p.x1, q.x0, q.x1));
        FUZZ_CHECK(deeper ? q.x1 == p.x1 && q.x0 >= p.x0 : q.x0 <= p.x0 && q.x1 >= p.x1);
        break;
    default:
        FUZZ_CHECK(q.y1 == p.y0 && overlap(p.x0, p.x1, q.x0, q.x1));
        FUZZ_CHECK(deeper ? q.x0 == p.x0 && q.x1 <= p.x1 : q.x0 <= p.x0 && q.x1 >= p.x1);
        break;
    }
}

static void locate(nav *n, int64_t x, int64_t y)
{
    hpfc_pixel px;
    int st = hpfc_locate(n->f, x, y, &px);
    check_status(st);
    bool inside = x >= n->info.x0 && y >= n->info.y0 && x - n->info.x0 < n->info.width &&
                  y - n->info.y0 < n->info.height;
    if (!inside) {
        FUZZ_CHECK(st == HPFC_E_NO_PIXEL);
        return;
    }
    FUZZ_CHECK(st != HPFC_E_NO_PIXEL && st != HPFC_E_ARG);
    box b;
    if (st || bounds(n, &px, &b))
        return;
    FUZZ_CHECK(b.x0 <= x && x < b.x1 && b.y0 <= y && y < b.y1);
    int type;
    FUZZ_CHECK(hpfc_pixel_type(n->f, &px, &type) == HPFC_OK && type == HPFC_PIXEL_WORD);
}

static void child(nav *n, const hpfc_pixel *px, uint32_t i, uint32_t j, hpfc_pixel *out)
{
    int st = hpfc_pixel_child(n->f, px, i, j, out);
    check_status(st);
    box p, c;
    if (st || bounds(n, px, &p) || bounds(n, out, &c))
        return;
    FUZZ_CHECK(out->depth == px->depth + 1);
    FUZZ_CHECK(p.x0 <= c.x0 && c.x1 <= p.x1 && p.y0 <= c.y0 && c.y1 <= p.y1);
}

/* No commands: every leaf in order, its word and its four moves. */
static void explore(nav *n)
{
    hpfc_pixel px;
    int st = hpfc_leaf_first(n->f, &px);
    check_status(st);
    while (!st && spend(n)) {
        decode(n, &px, sizeof n->word);
        for (int dir = HPFC_WEST; dir <= HPFC_SOUTH && spend(n); dir++)
            move(n, &px, dir);
        st = hpfc_leaf_next(n->f, &px);
        check_status(st);
    }
    for (int k = 0; k < 16 && spend(n); k++)
        locate(n, n->info.x0 + n->info.width * k / 16, n->info.y0 + n->info.height * (k * 7 % 16) / 16);
}

/* A coordinate near the domain: mostly inside, sometimes just outside. */
static int64_t coordinate(fuzz_bytes *in, int64_t origin, int64_t extent)
{
    uint64_t r = fuzz_u64(in);
    if ((r & 15) == 0)
        return origin - 1 + (int64_t)((r >> 4) % 3) * (extent + 1);
    return origin + (int64_t)((r >> 4) % (uint64_t)extent);
}

static void run_commands(nav *n, fuzz_bytes *in)
{
    hpfc_pixel cur = {0}, tmp = {0};
    int st = hpfc_pixel_root(n->f, 0, 0, &cur);
    check_status(st);
    if (st)
        return;
    while (!fuzz_empty(in) && spend(n)) {
        uint8_t op = fuzz_u8(in);
        switch (op % 12) {
        case 0: { /* a root pixel, sometimes out of range */
            uint32_t i = fuzz_u16(in) % (n->info.root_cols + 1);
            uint32_t j = fuzz_u16(in) % (n->info.root_rows + 1);
            st = hpfc_pixel_root(n->f, i, j, &tmp);
            check_status(st);
            FUZZ_CHECK((st == HPFC_OK) == (i < n->info.root_cols && j < n->info.root_rows));
            if (!st)
                cur = tmp;
            break;
        }
        case 1: {
            uint32_t i = fuzz_u8(in) % (n->info.cols + 1), j = fuzz_u8(in) % (n->info.rows + 1);
            child(n, &cur, i, j, &tmp);
            if (!hpfc_pixel_type(n->f, &tmp, &(int){0}) && tmp.depth == cur.depth + 1)
                cur = tmp;
            break;
        }
        case 2:
            st = hpfc_pixel_parent(&cur, &tmp);
            check_status(st);
            FUZZ_CHECK((st == HPFC_E_NO_PIXEL) == (cur.depth == 0));
            if (!st)
                cur = tmp;
            break;
        case 3: {
            int dir = (op >> 4) % 5; /* 4: an invalid direction */
            move(n, &cur, dir);
            if (dir < 4 && hpfc_pixel_move(n->f, &cur, dir, &tmp) == HPFC_OK)
                cur = tmp;
            break;
        }
        case 4: {
            int64_t x = coordinate(in, n->info.x0, n->info.width);
            int64_t y = coordinate(in, n->info.y0, n->info.height);
            locate(n, x, y);
            if (hpfc_locate(n->f, x, y, &tmp) == HPFC_OK)
                cur = tmp;
            break;
        }
        case 5:
            decode(n, &cur, fuzz_u8(in) % 64);
            break;
        case 6:
            decode(n, &cur, sizeof n->word);
            break;
        case 7: {
            box b;
            bounds(n, &cur, &b);
            break;
        }
        case 8:
            st = hpfc_leaf_first(n->f, &tmp);
            check_status(st);
            if (!st)
                cur = tmp;
            break;
        case 9:
            tmp = cur;
            st = hpfc_leaf_next(n->f, &tmp);
            check_status(st);
            if (!st)
                cur = tmp;
            break;
        case 10: { /* an untrusted pixel stack: another image offset */
            tmp = cur;
            tmp.path[tmp.depth].image = fuzz_u64(in) >> (fuzz_u8(in) % 64);
            decode(n, &tmp, sizeof n->word);
            for (int dir = 0; dir < 4; dir++)
                check_status(hpfc_pixel_move(n->f, &tmp, dir, &(hpfc_pixel){0}));
            box b;
            bounds(n, &tmp, &b);
            break;
        }
        default: { /* an untrusted pixel stack: depth and indices */
            tmp = cur;
            tmp.depth = fuzz_u8(in) % (HPFC_MAX_LEVELS + 2);
            if (tmp.depth < HPFC_MAX_LEVELS) {
                tmp.path[tmp.depth].i = fuzz_u8(in);
                tmp.path[tmp.depth].j = fuzz_u8(in);
            }
            decode(n, &tmp, sizeof n->word);
            box b;
            bounds(n, &tmp, &b);
            check_status(hpfc_pixel_move(n->f, &tmp, op >> 6, &(hpfc_pixel){0}));
            break;
        }
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
        nav n = {.f = f, .steps = FUZZ_STEPS};
        hpfc_file_get_info(f, &n.info);
        if (fuzz_empty(&cmds))
            explore(&n);
        else
            run_commands(&n, &cmds);
        hpfc_close(f);
    }
    free(file);
    return 0;
}
