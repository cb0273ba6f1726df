/*
 * Reader benchmark (its targets):
 *   (a) opening costs O(1) in the file size: at most 1 ms and 1 MB of
 *       resident memory for a file of 500 MB or more;
 *   (b) a random pixel fetched and its word decoded: at most 200 ns;
 *   (c) locate(x, y) at depth 16: at most 1 us.
 * (a) uses a synthetic 671 MB file: a 32768 x 32768 root of private pixels,
 * valid under the spec (a zero record is a word pixel with word "++++").
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "format.h"
#include "gen.h"
#include "hpfc.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long resident_kib(void)
{
    long pages = 0, resident = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (f) {
        if (fscanf(f, "%ld %ld", &pages, &resident) != 2)
            resident = 0;
        fclose(f);
    }
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* Writes the synthetic big file; returns its size or 0. */
static uint64_t write_big_file(const char *path)
{
    const uint32_t side = 32768;
    const uint64_t pixels = (uint64_t)side * side, pool_bits = 5 * pixels;
    const uint64_t meta = FORMAT_HEADER_SIZE + FORMAT_LEVEL_ENTRY_SIZE + FORMAT_SECTION_ENTRY_SIZE;
    const uint64_t pool_off = (meta + 7) / 8 * 8, pool_len = (pool_bits + 7) / 8, size = pool_off + pool_len;
    uint8_t head[512] = {0};
    memcpy(head, FORMAT_MAGIC, FORMAT_MAGIC_SIZE);
    hdr_set_format_major(head, 1);
    hdr_set_header_size(head, FORMAT_HEADER_SIZE);
    hdr_set_root_cols(head, side), hdr_set_root_rows(head, side);
    hdr_set_cols(head, 2), hdr_set_rows(head, 2);
    hdr_set_levels(head, 1);
    hdr_set_section_count(head, 1);
    hdr_set_width(head, side), hdr_set_height(head, side);
    hdr_set_file_size(head, size);
    hdr_set_meta_size(head, meta);
    uint8_t *lv = head + FORMAT_HEADER_SIZE, *sec = lv + FORMAT_LEVEL_ENTRY_SIZE;
    lvl_set_word_pixels(lv, pixels);
    lvl_set_images(lv, 1);
    lvl_set_word_bits(lv, 4);
    lvl_set_pool_offset(lv, pool_off);
    lvl_set_pool_bits(lv, pool_bits);
    memcpy(sec, FORMAT_TAG_POOL, 4);
    sec_set_flags(sec, 1);
    sec_set_offset(sec, pool_off);
    sec_set_length(sec, pool_len);
    /* CRC-32C of pool_len zero bytes, computed in 1 MiB steps */
    static uint8_t zeros[1 << 20];
    uint32_t crc = 0;
    for (uint64_t done = 0; done < pool_len; done += sizeof zeros)
        crc = crc32c_update(crc, zeros, (size_t)(pool_len - done < sizeof zeros ? pool_len - done : sizeof zeros));
    sec_set_crc32c(sec, crc);
    hdr_set_meta_crc32c(head, format_meta_crc(head, meta));
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0)
        return 0;
    bool ok = ftruncate(fd, (off_t)size) == 0 && pwrite(fd, head, (size_t)meta, 0) == (ssize_t)meta;
    close(fd);
    return ok ? size : 0;
}

static void bench_open(void)
{
    char path[] = "/tmp/hpfc-bench-big.hpfc";
    uint64_t size = write_big_file(path);
    if (!size) {
        printf("(a) could not write %s\n", path);
        return;
    }
    double best = 1e9, sum = 0;
    long rss_delta = 0;
    const int runs = 50;
    for (int r = 0; r < runs; r++) {
        long before = resident_kib();
        hpfc_file *f = NULL;
        double t0 = now();
        int st = hpfc_open(path, 0, &f);
        double t = now() - t0;
        long after = resident_kib();
        if (st) {
            printf("(a) open failed: %s\n", hpfc_strerror(st));
            break;
        }
        hpfc_pixel px;
        int is_private = 0; /* one read at the far end, to show the file is usable */
        hpfc_pixel_root(f, 32767, 32767, &px);
        hpfc_pixel_is_private(f, &px, &is_private);
        hpfc_close(f);
        best = t < best ? t : best;
        sum += t;
        if (after - before > rss_delta)
            rss_delta = after - before;
    }
    printf("(a) open of a %.0f MB file: best %.1f us, mean %.1f us over %d opens; resident memory grows by at most %ld KiB\n",
           (double)size / 1e6, best * 1e6, sum / runs * 1e6, runs, rss_delta);
    unlink(path);
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return rng_state;
}

/* Both pool layouts in one run: A/B. */
static const struct {
    int layout;
    const char *name;
} layouts[2] = {{HPFC_LAYOUT_PAPER, "paper"}, {HPFC_LAYOUT_COMPACT, "compact"}};

static hpfc_file *pack_graph(hpfc_graph *g, uint8_t **buf, int layout)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    size_t size;
    hpfc_write_options o = {.layout = layout};
    if (hpfc_build(g, &p, &t, NULL) || hpfc_tree_serialize(t, &o, buf, &size, NULL) ||
        hpfc_open_memory(*buf, size, 0, &f))
        f = NULL;
    hpfc_tree_free(t);
    return f;
}

/* (b): leaves found at random points, then fetched and decoded in turn. */
static void bench_fetch(int layout, const char *name, int rounds)
{
    hpfc_graph *g = NULL;
    uint8_t *buf = NULL;
    rng_state = 0x9E3779B97F4A7C15ull; /* the same points for both layouts */
    if (gen_grid_mesh(3, 300, 300, 64, &g))
        return;
    hpfc_file *f = pack_graph(g, &buf, layout);
    if (!f)
        return;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    enum { N = 4096 };
    hpfc_pixel *px = malloc(N * sizeof *px);
    for (int k = 0; k < N; k++)
        hpfc_locate(f, info.x0 + (int64_t)(rng() % (uint64_t)info.width),
                    info.y0 + (int64_t)(rng() % (uint64_t)info.height), &px[k]);
    char word[4096];
    size_t len, total = 0;
    double t0 = now();
    for (int r = 0; r < rounds; r++)
        for (int k = 0; k < N; k++) {
            int type;
            hpfc_pixel_type(f, &px[k], &type);
            hpfc_pixel_word(f, &px[k], word, sizeof word, &len);
            total += len;
        }
    double t = now() - t0;
    printf("(b) %-7s fetch + decode of random leaf pixels (grid mesh 300x300, %.0f KB file, %.1f bits/edge): "
           "%.1f ns each (mean word %.1f symbols)\n",
           name, (double)info.file_size / 1e3, 8.0 * (double)info.file_size / (double)hpfc_graph_edge_count(g),
           rounds ? 1e9 * t / (rounds * N) : 0.0, rounds ? (double)total / (rounds * N) : 0.0);
    free(px);
    hpfc_close(f);
    free(buf);
    hpfc_graph_free(g);
}

/* (c): a frame 2^24 wide with one edge of length 1 inside: the leaves
 * around that edge are 17 to 19 levels deep. */
static void bench_locate_deep(int layout, const char *name)
{
    hpfc_graph *g;
    hpfc_graph_create(&g);
    const int64_t S = (int64_t)1 << 24, c = 5000003;
    hpfc_graph_add_vertex(g, 0, 0, NULL), hpfc_graph_add_vertex(g, S, 0, NULL);
    hpfc_graph_add_vertex(g, S, S, NULL), hpfc_graph_add_vertex(g, 0, S, NULL);
    hpfc_graph_add_vertex(g, c, c, NULL), hpfc_graph_add_vertex(g, c + 1, c, NULL);
    for (uint32_t k = 0; k < 4; k++)
        hpfc_graph_add_edge(g, k, (k + 1) % 4, NULL, 0, NULL);
    hpfc_graph_add_edge(g, 4, 5, NULL, 0, NULL);
    uint8_t *buf = NULL;
    rng_state = 0x9E3779B97F4A7C15ull;
    hpfc_file *f = pack_graph(g, &buf, layout);
    if (!f)
        return;
    enum { N = 4096 };
    int64_t *xy = malloc(2 * N * sizeof *xy);
    size_t kept = 0;
    double depth_sum = 0;
    for (int k = 0; k < 64 * N && kept < N; k++) { /* points whose leaf is 16+ deep */
        int64_t x = c - 64 + (int64_t)(rng() % 130), y = c - 64 + (int64_t)(rng() % 130);
        hpfc_pixel px;
        if (hpfc_locate(f, x, y, &px) == HPFC_OK && px.depth >= 16) {
            xy[2 * kept] = x, xy[2 * kept + 1] = y, kept++;
            depth_sum += px.depth;
        }
    }
    const int rounds = 100;
    hpfc_pixel px;
    double t0 = now();
    for (int r = 0; r < rounds; r++)
        for (size_t k = 0; k < kept; k++)
            hpfc_locate(f, xy[2 * k], xy[2 * k + 1], &px);
    double t = now() - t0;
    printf("(c) %-7s locate at depth >= 16 (mean depth %.1f over %zu points): %.1f ns each\n", name,
           depth_sum / (double)kept, kept, 1e9 * t / (double)(rounds * kept));
    free(xy);
    hpfc_close(f);
    free(buf);
    hpfc_graph_free(g);
}

/* `bench_read fetch paper|compact ROUNDS` runs only (b)'s loop, ROUNDS
 * times: bench/run-ab.sh counts its instructions under cachegrind as the
 * difference of two ROUNDS, which cancels the packing and the locates. */
int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "fetch") == 0) {
        int k = strcmp(argv[2], "compact") == 0;
        bench_fetch(layouts[k].layout, layouts[k].name, atoi(argv[3]));
        return 0;
    }
    bench_open();
    for (int round = 0; round < 2; round++) /* A B A B: the machine drifts */
        for (int k = 0; k < 2; k++)
            bench_fetch(layouts[k].layout, layouts[k].name, 200);
    for (int round = 0; round < 2; round++)
        for (int k = 0; k < 2; k++)
            bench_locate_deep(layouts[k].layout, layouts[k].name);
    return 0;
}
