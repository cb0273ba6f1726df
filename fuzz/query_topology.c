/*
 * query_topology: the topology questions over the hpfc_shapes index
 * (hpfc_shapes_feature_neighbours, _adjacency, _nearest_edge,
 * _edges_within, _features_polygons, _mesh) on an opened file, driven by
 * the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated GEOM, LABL, FEAT and EDGF
 * sections reach the walks. Without commands: the neighbours of the first
 * 64 features and one past, both adjacencies, the nearest edge to 16 points
 * over and around the domain (of the map and of a feature), the edges
 * within a distance of them, the union of every feature alone and of all,
 * the mesh of each kind by feature and by a derived field. With commands:
 * input-chosen features (any 64-bit id), points (domain-relative or any
 * value, out of range included), distances and sets.
 *
 * Oracle: known statuses (and NO_SECTION) only; ids past the end and
 * points past the lattice are HPFC_E_ARG; answers well formed: neighbour
 * ids ascending, never the feature itself, touch 1 or 2, a vertex touch
 * with no edge and length 0, edges in range; adjacency pairs a < b,
 * strictly increasing; a nearest edge in range, its segment below its
 * point count, its distance finite and not below 0; within d: ascending
 * edges each at most d (rounded). (That the nearest edge is among those
 * within a larger d holds for valid files only, and test_queries checks
 * it there: a damaged LABL can list an edge in a leaf its closest point
 * is not in, and the two searches then read different leaves.)
 * unions as rings (closed, outer counter-clockwise), mesh lines open.
 */
#include <math.h>

#include "input.h"

__extension__ typedef __int128 s128;

static void check_status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st) || st == HPFC_E_NO_SECTION);
}

typedef struct qz {
    const hpfc_file *f;
    hpfc_shapes *s;
    uint64_t edges;
    uint32_t features;
    int64_t dom[4];
} qz;

static void check_rings(const hpfc_polygons *p, int lines)
{
    FUZZ_CHECK(p->ring_point[0] == 0 && p->ring_point[p->ring_count] == p->point_count);
    FUZZ_CHECK(p->polygon_ring[p->polygon_count] <= p->ring_count);
    if (lines)
        FUZZ_CHECK(p->polygon_count == 0 && p->polygon_ring[0] == p->ring_count);
    for (size_t r = 0; r < p->ring_count; r++) {
        size_t a = p->ring_point[r], b = p->ring_point[r + 1];
        FUZZ_CHECK(a <= b && b <= p->point_count && b - a >= 2);
        if (lines)
            continue;
        FUZZ_CHECK(b - a >= 4 && p->xy[2 * a] == p->xy[2 * (b - 1)] &&
                   p->xy[2 * a + 1] == p->xy[2 * (b - 1) + 1]);
        s128 area = 0;
        for (size_t k = a; k + 1 < b; k++)
            area += (s128)p->xy[2 * k] * p->xy[2 * k + 3] - (s128)p->xy[2 * k + 2] * p->xy[2 * k + 1];
        int outer = 0;
        for (size_t q = 0; q < p->polygon_count; q++)
            outer |= p->polygon_ring[q] == r;
        FUZZ_CHECK(outer ? area > 0 : area < 0);
    }
}

static void probe_neighbours(qz *z, hpfc_id g)
{
    hpfc_neighbours nb;
    int st = hpfc_shapes_feature_neighbours(z->s, g, &nb);
    check_status(st);
    if (st != HPFC_E_NO_SECTION && g >= z->features)
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (st)
        return;
    FUZZ_CHECK(nb.edge_start[0] == 0);
    for (size_t k = 0; k < nb.count; k++) {
        FUZZ_CHECK(nb.feature[k] < z->features && nb.feature[k] != g);
        FUZZ_CHECK(k == 0 || nb.feature[k - 1] < nb.feature[k]);
        FUZZ_CHECK(nb.touch[k] == HPFC_TOUCH_EDGE || nb.touch[k] == HPFC_TOUCH_VERTEX);
        size_t a = nb.edge_start[k], b = nb.edge_start[k + 1];
        FUZZ_CHECK(a <= b && (nb.touch[k] == HPFC_TOUCH_EDGE) == (b > a));
        FUZZ_CHECK(nb.length[k] >= 0 && (b > a || nb.length[k] == 0));
        for (size_t j = a; j < b; j++)
            FUZZ_CHECK(nb.edge[j] < z->edges && (j == a || nb.edge[j - 1] < nb.edge[j]));
    }
}

static void probe_adjacency(qz *z, unsigned touch)
{
    hpfc_adjacency adj;
    int st = hpfc_shapes_adjacency(z->s, touch, &adj);
    check_status(st);
    if (st)
        return;
    for (size_t k = 0; k < adj.count; k++) {
        FUZZ_CHECK(adj.a[k] < adj.b[k] && adj.b[k] < z->features);
        FUZZ_CHECK(k == 0 || adj.a[k - 1] < adj.a[k] ||
                   (adj.a[k - 1] == adj.a[k] && adj.b[k - 1] < adj.b[k]));
        FUZZ_CHECK(adj.touch[k] == HPFC_TOUCH_EDGE ||
                   (adj.touch[k] == HPFC_TOUCH_VERTEX && (touch & HPFC_TOUCH_VERTEX)));
    }
}

static int point_ok(int64_t x, int64_t y)
{
    return x >= -HPFC_LATTICE_MAX && x <= HPFC_LATTICE_MAX && y >= -HPFC_LATTICE_MAX &&
           y <= HPFC_LATTICE_MAX;
}

static void probe_point(qz *z, int64_t x, int64_t y, hpfc_id feature, int64_t d)
{
    hpfc_nearest r;
    int st = hpfc_shapes_nearest_edge(z->s, x, y, feature, &r);
    check_status(st);
    if (!point_ok(x, y) || (feature != HPFC_ID_NONE && feature >= z->features &&
                            st != HPFC_E_NO_SECTION))
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (!st) {
        uint64_t u, v, n = 0;
        FUZZ_CHECK(r.edge < z->edges);
        FUZZ_CHECK(hpfc_geometry_edge(z->f, r.edge, &u, &v, &n) == HPFC_OK && r.segment + 1 < n);
        FUZZ_CHECK(r.distance >= 0 && isfinite(r.distance) && isfinite(r.x) && isfinite(r.y));
    }
    hpfc_edge_hits h;
    int st2 = hpfc_shapes_edges_within(z->s, x, y, d, &h);
    check_status(st2);
    if (!point_ok(x, y) || d < 0 || d > 2 * HPFC_LATTICE_MAX)
        FUZZ_CHECK(st2 == HPFC_E_ARG);
    if (st2)
        return;
    for (size_t k = 0; k < h.count; k++) {
        FUZZ_CHECK(h.edge[k] < z->edges && (k == 0 || h.edge[k - 1] < h.edge[k]));
        FUZZ_CHECK(h.distance[k] >= 0 && h.distance[k] <= (double)d * (1 + 1e-9) + 1e-9);
    }
}

static void probe_union(qz *z, const hpfc_id *set, size_t n)
{
    hpfc_polygons p;
    int st = hpfc_shapes_features_polygons(z->s, set, n, &p);
    check_status(st);
    for (size_t k = 0; k < n; k++)
        if (set[k] >= z->features && st != HPFC_E_NO_SECTION)
            FUZZ_CHECK(st == HPFC_E_ARG);
    if (!st)
        check_rings(&p, 0);
}

static void probe_mesh(qz *z, const uint32_t *group, size_t n, unsigned sides)
{
    hpfc_polygons p;
    int st = hpfc_shapes_mesh(z->s, group, n, sides, &p);
    check_status(st);
    if (!sides || sides > 3)
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (!st)
        check_rings(&p, 1);
}

static void explore(qz *z)
{
    for (uint32_t g = 0; g < z->features && g < 64; g++)
        probe_neighbours(z, g);
    probe_neighbours(z, z->features);
    probe_adjacency(z, HPFC_TOUCH_EDGE);
    probe_adjacency(z, HPFC_TOUCH_EDGE | HPFC_TOUCH_VERTEX);
    probe_adjacency(z, HPFC_TOUCH_VERTEX);
    int64_t w = z->dom[2] - z->dom[0], h = z->dom[3] - z->dom[1];
    for (int k = 0; k < 16; k++) {
        int64_t x = z->dom[0] - w / 4 + (int64_t)((k * 7) % 16) * (w + w / 2) / 15;
        int64_t y = z->dom[1] - h / 4 + (int64_t)((k * 5) % 16) * (h + h / 2) / 15;
        probe_point(z, x, y, k % 4 ? HPFC_ID_NONE : (hpfc_id)k / 4, (w + h) / 64 * (k % 3));
    }
    probe_point(z, HPFC_LATTICE_MAX + 1, 0, HPFC_ID_NONE, 0);
    for (uint32_t g = 0; g < z->features && g < 64; g++) {
        hpfc_id one = g;
        probe_union(z, &one, 1);
    }
    hpfc_id all[64];
    size_t n = 0;
    for (uint32_t g = 0; g < z->features && g < 64; g++)
        all[n++] = g;
    probe_union(z, all, n);
    uint32_t *field = malloc(((size_t)z->features + 1) * sizeof *field);
    if (field) {
        for (uint32_t g = 0; g < z->features; g++)
            field[g] = g % 3 == 2 ? HPFC_GROUP_NONE : g % 2;
        for (unsigned sides = 1; sides <= 3; sides++) {
            probe_mesh(z, NULL, 0, sides);
            probe_mesh(z, field, z->features, sides);
        }
        free(field);
    }
}

static void run_commands(qz *z, fuzz_bytes *in)
{
    int64_t w = z->dom[2] - z->dom[0] + 1, h = z->dom[3] - z->dom[1] + 1;
    for (int steps = 0; steps < 48 && !fuzz_empty(in); steps++) {
        uint8_t op = fuzz_u8(in);
        switch (op % 5) {
        case 0:
            probe_neighbours(z, op & 8 ? fuzz_u64(in) : fuzz_u16(in) % (z->features + 1));
            break;
        case 1:
            probe_adjacency(z, fuzz_u8(in) % 5);
            break;
        case 2: {
            int64_t x, y;
            if (op & 8) {
                x = (int64_t)fuzz_u64(in), y = (int64_t)fuzz_u64(in);
            } else {
                x = z->dom[0] - w + (int64_t)(fuzz_u32(in) % (uint64_t)(3 * w));
                y = z->dom[1] - h + (int64_t)(fuzz_u32(in) % (uint64_t)(3 * h));
            }
            hpfc_id g = op & 16 ? fuzz_u16(in) % (z->features + 1) : HPFC_ID_NONE;
            int64_t d = op & 32 ? (int64_t)fuzz_u64(in) : (int64_t)(fuzz_u16(in) % (w + 1));
            probe_point(z, x, y, g, d);
            break;
        }
        case 3: {
            hpfc_id set[8];
            size_t n = fuzz_u8(in) % 9;
            for (size_t k = 0; k < n; k++)
                set[k] = op & 8 ? fuzz_u64(in) : fuzz_u16(in) % (z->features + 1);
            probe_union(z, set, n);
            break;
        }
        default: {
            unsigned sides = fuzz_u8(in) % 5;
            uint32_t *group = malloc(((size_t)z->features + 1) * sizeof *group);
            if (!group)
                break;
            uint8_t mod = fuzz_u8(in);
            for (uint32_t g = 0; g < z->features; g++)
                group[g] = mod ? g % mod : HPFC_GROUP_NONE;
            probe_mesh(z, op & 8 ? NULL : group, z->features - (op & 16 ? 1 : 0), sides);
            free(group);
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
        qz z = {.f = f};
        int st = hpfc_shapes_create(f, &z.s);
        check_status(st);
        if (st == HPFC_OK) {
            hpfc_geometry_info gi;
            z.edges = hpfc_file_get_geometry(f, &gi) == HPFC_OK ? gi.edges : 0;
            hpfc_features_info fi;
            z.features = hpfc_file_get_features(f, &fi) == HPFC_OK ? fi.features : 0;
            hpfc_file_info info;
            hpfc_file_get_info(f, &info);
            z.dom[0] = info.x0, z.dom[1] = info.y0;
            z.dom[2] = info.x0 + info.width - 1, z.dom[3] = info.y0 + info.height - 1;
            if (fuzz_empty(&cmds))
                explore(&z);
            else
                run_commands(&z, &cmds);
        }
        hpfc_shapes_free(z.s);
        hpfc_close(f);
    }
    free(file);
    return 0;
}
