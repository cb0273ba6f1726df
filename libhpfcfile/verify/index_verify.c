/*
 * hpfc_index_verify: the SHIX section (spec/hpfc-format.md §6.8) against
 * the LABL, FEAT and EDGF sections it inverts (§6.8.4).
 *
 * Each stored row is read with the access check (shix_row: ids strictly
 * ascending, each the inverse of a link of the section it inverts), and
 * each table's link count is compared with the number of links it must
 * invert. A table of distinct true pairs with the right count is the
 * whole inverse, so the two together prove the table equal to the one the
 * writer computes, without building it.
 */
#include <inttypes.h>

#include "feat.h"
#include "attrs.h"
#include "file.h"
#include "shix.h"
#include "verify_report.h"

#define FAIL(...) verify_message(rep->message, sizeof rep->message, __VA_ARGS__)

/* Every row of table t read as an access reads it, its offsets running
 * from 0 to its link count. */
static int check_rows(const shix_table *t, const shix_inverse *of, const char *what,
                      hpfc_index_report *rep)
{
    for (uint64_t row = 0; row < t->rows; row++) {
        uint64_t a, b;
        if (shix_row(t, row, of, &a, &b))
            return FAIL("shape index: %s row %" PRIu64 " is not the inverse of its section", what,
                        row);
        if ((row == 0 && a != 0) || (row + 1 == t->rows && b != t->links))
            return FAIL("shape index: the %s index does not run from 0 to its %u links", what,
                        t->links);
        rep->rows_checked++;
    }
    return HPFC_OK;
}

/* The links the face table must hold: two for each edge with two faces. */
static uint64_t face_links_due(const labels_view *lv)
{
    uint64_t n = 0;
    for (uint64_t e = 0; e < lv->edges; e++)
        n += 2 * (format_get(&lv->sides, 2 * e * lv->face_bits, lv->face_bits) !=
                  format_get(&lv->sides, (2 * e + 1) * lv->face_bits, lv->face_bits));
    return n;
}

/* Which feature tables the writer stores for this file (§6.8.3), and the
 * FEAT and EDGF links they invert. */
static int feature_tables_due(const hpfc_file *f, uint32_t *tables, uint32_t *features,
                              feature_links *face_links, feature_links *edge_links)
{
    hpfc_features_info fi;
    *tables = 0, *features = 0;
    int st = hpfc_file_get_features(f, &fi);
    if (st == HPFC_E_NO_SECTION)
        return HPFC_OK;
    if (st || (st = features_face_links(f, true, face_links)))
        return st;
    *features = fi.features;
    if (fi.faces == f->labels.faces)
        *tables |= SHIX_FEATURE_FACES;
    st = attrs_edge_links(f, true, edge_links);
    if (st == HPFC_E_NO_SECTION)
        return HPFC_OK;
    if (st)
        return st;
    if (edge_links->rows == f->labels.edges && edge_links->features == fi.features)
        *tables |= SHIX_FEATURE_EDGES;
    return HPFC_OK;
}

int hpfc_index_verify(const hpfc_file *file, hpfc_index_report *rep)
{
    if (!file || !rep)
        return HPFC_E_ARG;
    *rep = (hpfc_index_report){0};
    const shix_view *x = &file->shix;
    const labels_view *lv = &file->labels;
    if (!x->present)
        return HPFC_E_NO_SECTION;
    if (!lv->present)
        return FAIL("shape index: a SHIX section without LABL");
    if (x->faces != lv->faces || x->edges != lv->edges)
        return FAIL("shape index: %u faces and %u edges, LABL has %" PRIu64 " and %" PRIu64,
                    x->faces, x->edges, lv->faces, lv->edges);
    uint32_t tables, features;
    feature_links face_links = {0}, edge_links = {0};
    int st = feature_tables_due(file, &tables, &features, &face_links, &edge_links);
    if (st)
        return st == HPFC_E_CORRUPT ? FAIL("shape index: FEAT or EDGF does not read") : st;
    if (x->features != features || x->tables != tables)
        return FAIL("shape index: %u features with tables %u, the file calls for %u with tables %u",
                    x->features, x->tables, features, tables);
    shix_inverse sides = {.labels = lv};
    if ((st = check_rows(&x->face_edges, &sides, "face", rep)))
        return st;
    if (x->face_edges.links != face_links_due(lv))
        return FAIL("shape index: %u face links, LABL calls for %" PRIu64, x->face_edges.links,
                    face_links_due(lv));
    shix_inverse of_faces = {.links = &face_links}, of_edges = {.links = &edge_links};
    if ((tables & SHIX_FEATURE_FACES) &&
        ((st = check_rows(&x->feature_faces, &of_faces, "feature-face", rep)) ||
         (x->feature_faces.links != face_links.links &&
          (st = FAIL("shape index: %u feature-face links, FEAT has %u", x->feature_faces.links,
                     face_links.links)))))
        return st;
    if ((tables & SHIX_FEATURE_EDGES) &&
        ((st = check_rows(&x->feature_edges, &of_edges, "feature-edge", rep)) ||
         (x->feature_edges.links != edge_links.links &&
          (st = FAIL("shape index: %u feature-edge links, EDGF has %u", x->feature_edges.links,
                     edge_links.links)))))
        return st;
    return HPFC_OK;
}
