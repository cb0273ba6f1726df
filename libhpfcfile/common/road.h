/*
 * road.h: a road, one side of a pixel's lattice box (spec/hpfc-format.md
 * §3.4-§3.6), in one place: its direction (hpfc.h's HPFC_WEST ..
 * HPFC_SOUTH, also the order of a word's roads), its extent and clockwise
 * run, the lattice points just inside and just across it (which name the
 * leaves on either side, cells being half-open), and whether and where a
 * segment crosses it, under geom.h's perturbation.
 *
 * Header only: the builder, the locators, the traversal and hpfc-inspect
 * (which reaches it through the library's include directory) all use it.
 */
#ifndef HPFC_ROAD_H
#define HPFC_ROAD_H

#include <stdbool.h>
#include <stdint.h>

#include "geom.h"
#include "hpfc.h"

/* A pixel's lattice box [x0, x1) x [y0, y1), as hpfc_pixel_bounds gives it. */
typedef struct road_box {
    int64_t x0, y0, x1, y1;
} road_box;

/* The road across from `road`: W-E, N-S. */
static inline int road_opposite(int road)
{
    return (road + 2) % 4;
}

/* Extent [lo, hi) of box b along the line of `road`. */
static inline void road_extent(const road_box *b, int road, int64_t *lo, int64_t *hi)
{
    bool vertical = road == HPFC_WEST || road == HPFC_EAST;
    *lo = vertical ? b->y0 : b->x0;
    *hi = vertical ? b->y1 : b->x1;
}

/* The coordinate of the grid line road `road` of box b lies on: x for W
 * and E, y for N and S. */
static inline int64_t road_line(const road_box *b, int road)
{
    switch (road) {
    case HPFC_WEST: return b->x0;
    case HPFC_EAST: return b->x1;
    case HPFC_NORTH: return b->y1;
    default: return b->y0;
    }
}

/* Whether the road's clockwise (word) order runs toward increasing
 * coordinates: W runs north, N east; E runs south, S west. */
static inline bool road_ascends(int road)
{
    return road == HPFC_WEST || road == HPFC_NORTH;
}

/* The lattice point at position t along road `road` of box b, on b's side
 * (inside = true) or just across the road (half-open cells: x1 and y1
 * belong to the neighbour). */
static inline void road_point(const road_box *b, int road, int64_t t, bool inside, int64_t *x,
                              int64_t *y)
{
    switch (road) {
    case HPFC_WEST: *x = inside ? b->x0 : b->x0 - 1, *y = t; break;
    case HPFC_EAST: *x = inside ? b->x1 - 1 : b->x1, *y = t; break;
    case HPFC_NORTH: *x = t, *y = inside ? b->y1 - 1 : b->y1; break;
    default: *x = t, *y = inside ? b->y0 : b->y0 - 1; break;
    }
}

/* Does segment pq cross road `road` of cell [x0,x1) x [y0,y1)? On success
 * *pos is its position and *entering whether pq goes into the cell there.
 * The W/E and S/N cases stay two mirror images: the perturbation rule
 * (geom.h) ends a vertical road's span with vpos_north_of, which breaks
 * ties by tilt, and a horizontal one's with hpos_east_of, which needs none. */
static inline bool cross_road(lpoint p, lpoint q, int road, int64_t x0,
                              int64_t y0, int64_t x1, int64_t y1,
                              line_pos *pos, bool *entering)
{
    switch (road) {
    case HPFC_WEST:
    case HPFC_EAST: {
        int64_t X = road == HPFC_WEST ? x0 : x1;
        if (!cross_vertical(p, q, X, pos) || !vpos_north_of(pos, y0) ||
            vpos_north_of(pos, y1))
            return false;
        bool eastward = q.x >= X;
        *entering = (road == HPFC_WEST) == eastward;
        return true;
    }
    default: {
        int64_t Y = road == HPFC_SOUTH ? y0 : y1;
        if (!cross_horizontal(p, q, Y, pos) || !hpos_east_of(pos, x0) ||
            hpos_east_of(pos, x1))
            return false;
        bool northward = q.y >= Y;
        *entering = (road == HPFC_SOUTH) == northward;
        return true;
    }
    }
}

/* Does segment pq meet the (perturbed, open) cell? */
static inline bool segment_meets_cell(lpoint p, lpoint q, int64_t x0,
                                      int64_t y0, int64_t x1, int64_t y1)
{
    if (point_in_cell(p, x0, y0, x1, y1) || point_in_cell(q, x0, y0, x1, y1))
        return true;
    line_pos pos;
    bool entering;
    for (int road = 0; road < 4; road++)
        if (cross_road(p, q, road, x0, y0, x1, y1, &pos, &entering))
            return true;
    return false;
}

#endif
