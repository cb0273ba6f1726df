/*
 * The compact pool layout's geometry (pool.h, spec/hpfc-format.md §5.3): the
 * sizes of a level from its counts, and where a pixel's type bits lie. What
 * the reader and the writer both need.
 */
#include "pool.h"

/* Bits of an unsigned integer: the width that holds 0 .. v. */
static uint32_t bit_width(uint64_t v)
{
    return v ? (uint32_t)(64 - __builtin_clzll(v)) : 0;
}

bool pool_level_sizes(pool_level *pl, uint64_t pixels, uint64_t refined, uint64_t stabbed,
                      uint64_t stream_bits)
{
    *pl = (pool_level){.pixels = pixels, .refined = refined, .stabbed = stabbed,
                       .stream_bits = stream_bits};
    pl->refined_width = bit_width(refined);
    pl->stabbed_width = bit_width(stabbed);
    pl->blocks = pixels / POOL_BLOCK_PIXELS + (pixels % POOL_BLOCK_PIXELS != 0);
    uint64_t s, t;
    if (!format_mul(pl->blocks, (uint64_t)pl->refined_width + pl->stabbed_width, &s) ||
        !format_mul(pixels, 2, &t) || !format_add(s, t, &pl->type_bits))
        return false;
    pl->select_off = pl->low_off = pl->high_off = pl->stream_off = pl->pool_bits = pl->type_bits;
    if (stabbed == 0)
        return true;
    if (stabbed == UINT64_MAX)
        return false;
    pl->bounds = stabbed + 1;
    uint64_t q = stream_bits / pl->bounds;
    pl->low_width = q ? (uint32_t)(63 - __builtin_clzll(q)) : 0;
    if (!format_add(pl->bounds, stream_bits >> pl->low_width, &pl->high_bits))
        return false;
    pl->select_width = bit_width(pl->high_bits - 1);
    pl->select_count = pl->bounds / POOL_SELECT_STRIDE + (pl->bounds % POOL_SELECT_STRIDE != 0);
    pl->select_off = pl->type_bits;
    return format_mul(pl->select_count, pl->select_width, &s) &&
           format_add(pl->select_off, s, &pl->low_off) &&
           format_mul(pl->bounds, pl->low_width, &s) && format_add(pl->low_off, s, &pl->high_off) &&
           format_add(pl->high_off, pl->high_bits, &pl->stream_off) &&
           format_add(pl->stream_off, stream_bits, &pl->pool_bits);
}

/* ---- pixels ---------------------------------------------------------------------- */

uint64_t pool_type_bit(const pool_level *pl, uint64_t g)
{
    (void)pl;
    return 2 * g;
}

bool pool_pixel_at_bit(const pool_level *pl, uint64_t bit, uint64_t *g)
{
    if (bit % 2 || bit / 2 >= pl->pixels)
        return false;
    *g = bit / 2;
    return true;
}

