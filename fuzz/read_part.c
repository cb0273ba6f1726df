/*
 * read_part: a part file (spec/part-format.md), the tree of one part of a
 * split build (hpfc_build_part) as another process hands it to the merge.
 *
 * The input is a part file. Its trailing CRC-32C is set anew over the
 * input first (the library has no flag to skip it), so that mutations reach
 * the structure. Then hpfc_tree_read_part_memory; when it accepts, the
 * tree's pixels through hpfc_tree_get_pixel, the file written again
 * (part_serialize), the part merged alone (which succeeds only when it
 * holds every root pixel) and the merged tree serialised with LABL.
 *
 * Oracle: the reader's statuses only (magic, version, corrupt, memory), and a diagnostic with every failure; an
 * accepted file is canonical: written again it gives the input's bytes
 * (the reader accepts only what the builder can make, so nothing it
 * ignores can differ); its pixels are words of the grammar's symbols with
 * edges below the map's count, or refined pixels whose child is an image
 * of the next level; a merge of the part alone succeeds exactly when no
 * root pixel is another part's.
 */
#include "format.h"
#include "input.h"
#include "part_file.h"

/* What reading a part file may answer. */
static bool read_status(int st)
{
    return st == HPFC_OK || st == HPFC_E_NOMEM || st == HPFC_E_MAGIC || st == HPFC_E_VERSION ||
           st == HPFC_E_CORRUPT;
}

static bool has_other_parts_pixel(const hpfc_tree *t, const hpfc_tree_info *info)
{
    for (uint32_t j = 0; j < info->root_rows; j++)
        for (uint32_t i = 0; i < info->root_cols; i++) {
            hpfc_tree_pixel px;
            if (hpfc_tree_get_pixel(t, 0, 0, i, j, &px) == HPFC_E_ARG)
                return true;
        }
    return false;
}

static void check_pixels(const hpfc_tree *t, const hpfc_tree_info *info)
{
    for (uint32_t l = 0; l < info->levels; l++) {
        size_t images = hpfc_tree_image_count(t, l), visited = 0;
        uint32_t cols = l ? info->cols : info->root_cols, rows = l ? info->rows : info->root_rows;
        for (size_t im = 0; im < images && visited < 4096; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++, visited++) {
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(t, l, im, i, j, &px);
                    FUZZ_CHECK(st == HPFC_OK || (st == HPFC_E_ARG && l == 0));
                    if (st)
                        continue;
                    if (px.type == HPFC_PIXEL_REFINED) {
                        FUZZ_CHECK(px.child < hpfc_tree_image_count(t, l + 1));
                        continue;
                    }
                    FUZZ_CHECK(px.word_len >= 4 && px.word_len <= info->max_word_symbols + 4);
                    for (uint32_t k = 0; k < px.word_len; k++)
                        FUZZ_CHECK(strchr("+=[]()Y", px.word[k]) != NULL);
                    for (uint32_t k = 0; k + 4 < px.word_len; k++)
                        FUZZ_CHECK(px.cross_edge[k] < info->edges);
                }
    }
}

static void merge_alone(hpfc_tree *t, const hpfc_tree_info *info)
{
    hpfc_tree *joined = NULL;
    hpfc_diag d;
    int st = hpfc_tree_merge(&t, 1, &joined, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK(fuzz_known_status(st));
    if (has_other_parts_pixel(t, info))
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (st)
        return;
    uint8_t *bytes = NULL;
    size_t size = 0;
    hpfc_write_options o = {.face_labels = 1};
    st = hpfc_tree_serialize(joined, &o, &bytes, &size, &d);
    fuzz_check_diag(&d, st); /* a map of hostile words may fail to number its faces */
    hpfc_free(bytes);
    hpfc_tree_free(joined);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    memcpy(copy, data, size);
    if (size >= PART_CRC_SIZE)
        le_store(copy + size - PART_CRC_SIZE, 4, crc32c_update(0, copy, size - PART_CRC_SIZE));
    hpfc_tree *t = NULL;
    hpfc_diag d;
    int st = hpfc_tree_read_part_memory(copy, size, &t, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK(read_status(st));
    FUZZ_CHECK((st == HPFC_OK) == (t != NULL));
    if (!st) {
        hpfc_tree_info info;
        hpfc_tree_get_info(t, &info);
        check_pixels(t, &info);
        uint8_t *again = NULL;
        size_t again_size = 0;
        FUZZ_CHECK(part_serialize(t, &again, &again_size, &d) == HPFC_OK);
        FUZZ_CHECK(again_size == size && memcmp(again, copy, size) == 0);
        free(again);
        merge_alone(t, &info);
    }
    hpfc_tree_free(t);
    free(copy);
    return 0;
}
