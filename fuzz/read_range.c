/*
 * read_range: a range file (hpfc-pack/gis_range.h), a run of a GIS layer's
 * features that another process read, as hpfc-pack --read-ranges takes it
 * back: decoded, then loaded into the read of the layer it belongs to,
 * projected, noded and made a graph (gis_read_graph with opt.ranges).
 *
 * Once per process: a small lon/lat layer in a GDAL in-memory file (a
 * polygon with a hole, a line across it, an empty and a point feature, a
 * ring across the antimeridian, a bow-tie), read whole (the oracle) and
 * read as one range (gis_read_range: the genuine range file). Per input:
 * the bytes are the file's payload; the harness sets the tag, layer and
 * first feature the reading expects and the length and hash in front (so
 * that mutations reach the data), writes it as the reading's DIR/range-0
 * and reads the layer with --fields all, --key name.
 *
 * Oracle: gis_range_decode refuses the bytes with a message, or reads them
 * and gis_range_encode gives the very same bytes back (the encoding is
 * canonical); the read fails with one line naming the range file when the
 * decoder refused it, else succeeds or fails with one line, and a graph it
 * gives passes hpfc_graph_validate and the checks of input.h. The genuine
 * payload gives the whole read's graph, features and report counts.
 */
#include <cpl_vsi.h>
#include <stdbool.h>
#include <unistd.h>

#include "gis_input.h"
#include "gis_range.h"
#include "input.h"

static const char LAYER[] =
    "{\"type\":\"FeatureCollection\",\"features\":["
    "{\"type\":\"Feature\",\"properties\":{\"n\":1,\"x\":0.5,\"name\":\"holed\"},"
    "\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[10,0],[10,10],[0,10],[0,0]],"
    "[[2,2],[4,2],[4,4],[2,4],[2,2]]]}},"
    "{\"type\":\"Feature\",\"properties\":{\"x\":-2.25,\"name\":\"line\"},"
    "\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[-5,5],[5,5.5],[15,6]]}},"
    "{\"type\":\"Feature\",\"properties\":{\"n\":3},\"geometry\":null},"
    "{\"type\":\"Feature\",\"properties\":{\"n\":4,\"name\":\"point\"},"
    "\"geometry\":{\"type\":\"Point\",\"coordinates\":[1,1]}},"
    "{\"type\":\"Feature\",\"properties\":{\"n\":5,\"name\":\"dateline\"},"
    "\"geometry\":{\"type\":\"MultiPolygon\",\"coordinates\":[[[[179,20],[-179,20],[-179,22],"
    "[179,22],[179,20]]],[[[20,20],[21,20],[21,21],[20,20]]]]}},"
    "{\"type\":\"Feature\",\"properties\":{\"n\":6,\"x\":1e300,\"name\":\"bow, tie\"},"
    "\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[[[30,30],[32,32],[32,30],[30,32],"
    "[30,30]]]}}]}";

static const char PATH[] = "/vsimem/read_range_layer.geojson";
enum { HEAD = 24, TAG_AT = 0, LAYER_AT = 8, BEGIN_AT = 16 };

static char dir[64];
static gis_options options;
static hpfc_graph *whole;       /* the layer read whole */
static gis_info whole_info;
static uint8_t *genuine;        /* its one range's file */
static size_t genuine_len;
static const uint8_t *input;    /* this run's payload */
static size_t input_len;

static void put_le(uint8_t *p, uint64_t v, int bytes)
{
    for (int k = 0; k < bytes; k++)
        p[k] = (uint8_t)(v >> (8 * k));
}

/* The payload as the reading's range file: its tag, layer 0 and first
 * feature 0 set, the magic, length and hash in front. */
static uint8_t *file_of(const uint8_t *payload, size_t n, uint64_t tag, size_t *len)
{
    uint8_t *f = malloc(HEAD + n + 1);
    FUZZ_CHECK(f != NULL);
    memcpy(f, GIS_RANGE_MAGIC, 8);
    memcpy(f + HEAD, payload, n);
    uint8_t *p = f + HEAD;
    if (n >= BEGIN_AT + 8) {
        put_le(p + TAG_AT, tag, 8);
        put_le(p + LAYER_AT, 0, 4);
        put_le(p + BEGIN_AT, 0, 8);
    }
    put_le(f + 8, n, 8);
    put_le(f + 16, gis_range_hash(p, n), 8);
    *len = HEAD + n;
    return f;
}

static int write_range(void *user, const gis_range_plan *ranges, size_t n, uint64_t tag)
{
    (void)user;
    FUZZ_CHECK(n == 1 && ranges[0].layer == 0 && ranges[0].begin == 0 && ranges[0].end < 0);
    size_t len;
    uint8_t *f = file_of(input, input_len, tag, &len);
    char path[96];
    snprintf(path, sizeof path, "%s/range-0", dir);
    FILE *out = fopen(path, "wb");
    FUZZ_CHECK(out && fwrite(f, 1, len, out) == len && fclose(out) == 0);
    /* the decoder alone: refused with a message, or canonical */
    gis_range g;
    char why[256] = "";
    if (gis_range_decode(f, len, tag, 0, 0, &g, why, sizeof why) == 0) {
        uint8_t *again = NULL;
        size_t again_len = 0;
        FUZZ_CHECK(gis_range_encode(&g, &again, &again_len) == 0);
        FUZZ_CHECK(again_len == len && memcmp(again, f, len) == 0);
        free(again);
        gis_range_free(&g);
        *(int *)user = 1;
    } else {
        FUZZ_CHECK(why[0] && !strpbrk(why, "\r\n"));
        *(int *)user = 0;
    }
    free(f);
    return 0;
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/read_range.XXXXXX");
    FUZZ_CHECK(mkdtemp(dir) != NULL);
    VSILFILE *mem = VSIFileFromMemBuffer(PATH, (GByte *)LAYER, sizeof LAYER - 1, FALSE);
    FUZZ_CHECK(mem != NULL);
    VSIFCloseL(mem);
    options = (gis_options){.vertex_model = GIS_VERTICES_JUNCTIONS,
                            .invalid_mode = GIS_INVALID_NODE,
                            .key_field = "name",
                            .fields = "all",
                            .threads = 1};
    char err[512];
    FUZZ_CHECK(gis_read_graph(PATH, &options, &whole, &whole_info, err, sizeof err) == 0);
    /* the layer's features as their one range */
    gis_range_plan all = {0, 0, -1};
    FUZZ_CHECK(gis_read_range(PATH, &options, &all, 0, &genuine, &genuine_len, err, sizeof err) == 0);
    FUZZ_CHECK(genuine_len > HEAD);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static bool ready;
    if (!ready) {
        setup();
        ready = true;
    }
    input = data, input_len = size;
    int decoded = -1;
    gis_ranges ranges = {1, dir, write_range, &decoded};
    gis_options o = options;
    o.ranges = &ranges;
    hpfc_graph *g = NULL;
    gis_info info;
    char err[512];
    memset(err, 'x', sizeof err);
    int st = gis_read_graph(PATH, &o, &g, &info, err, sizeof err);
    FUZZ_CHECK(decoded >= 0 && (st == 0 || st == 1) && (st == 0) == (g != NULL));
    FUZZ_CHECK(memchr(err, 0, sizeof err) != NULL);
    /* the genuine range (its field count too), whatever the tag, layer
     * and begin the input held */
    bool genuine_input = size == genuine_len - HEAD &&
                         memcmp(data + LAYER_AT + 4, genuine + HEAD + LAYER_AT + 4, 4) == 0 &&
                         memcmp(data + BEGIN_AT + 8, genuine + HEAD + BEGIN_AT + 8,
                                size - BEGIN_AT - 8) == 0;
    FUZZ_CHECK(!genuine_input || (decoded && st == 0));
    if (st) {
        FUZZ_CHECK(err[0] && !strpbrk(err, "\r\n"));
        FUZZ_CHECK(decoded || strstr(err, "range-0: ") != NULL);
        return 0;
    }
    FUZZ_CHECK(decoded);
    fuzz_check_graph(g);
    FUZZ_CHECK(hpfc_graph_validate(g, NULL) == HPFC_OK);
    if (genuine_input) {
        FUZZ_CHECK(fuzz_same_graph(g, whole));
        FUZZ_CHECK(gis_features_count(info.polygons) == gis_features_count(whole_info.polygons));
        FUZZ_CHECK(info.features == whole_info.features &&
                   info.skipped_empty == whole_info.skipped_empty &&
                   info.skipped_points == whole_info.skipped_points &&
                   info.dateline_cut == whole_info.dateline_cut &&
                   info.invalid_noded == whole_info.invalid_noded &&
                   strcmp(info.repaired, whole_info.repaired) == 0);
    }
    hpfc_graph_free(g);
    gis_info_free(&info);
    return 0;
}
