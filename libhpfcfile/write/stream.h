/* stream.h: a section's bytes handed to the file as they are made, a
 * bounded buffer at a time, so that the writer never holds a section
 * that it can make in order (GEOM, from the graph and the tree).
 * Internal to the writer. */
#ifndef HPFC_STREAM_H
#define HPFC_STREAM_H

#include <stdbool.h>
#include <stdint.h>

/* Where the bytes go: put(ctx, offset, bytes, length) stores them at a
 * file offset (the writer's memory image, or pwrite). */
typedef struct stream_target {
    void (*put)(void *ctx, uint64_t offset, const uint8_t *bytes, uint64_t length);
    void *ctx;
} stream_target;

/* Bytes buffered before they are put: large enough that a put costs
 * little, small enough that a writer with a dozen streams holds no more
 * than a few of them at once. */
#define BITOUT_BYTES ((uint64_t)1 << 16)

/* A region of the file [at, at + length) written as a bit stream, most
 * significant bit first (spec §2.2), from its first bit on. */
typedef struct bitout {
    stream_target to;
    uint64_t at, length;
    uint64_t put;       /* bytes of the region put so far */
    uint64_t bit;       /* bits in buf */
    uint32_t crc;       /* CRC-32C of the bytes put */
    bool overrun;       /* more bits than the region holds */
    uint8_t buf[BITOUT_BYTES + 16];
} bitout;

/* A new stream over [at, at + length): NULL when out of memory. */
bitout *bitout_new(stream_target to, uint64_t at, uint64_t length);
/* Appends the k low bits of v (k <= 64). */
void bitout_put(bitout *b, unsigned k, uint64_t v);
/* Puts what is left; false when the bits written do not end in the
 * region's last byte. *crc: the CRC-32C of the bytes put. Frees b. */
bool bitout_finish(bitout *b, uint32_t *crc);
void bitout_free(bitout *b);

#endif
