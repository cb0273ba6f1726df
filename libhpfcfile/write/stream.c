/*
 * A region of the file written as a bit stream through a bounded buffer
 * (stream.h). Full bytes are put as soon as the buffer fills; the byte
 * the last value ended in stays, since the next value's bits go into it.
 */
#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "stream.h"

bitout *bitout_new(stream_target to, uint64_t at, uint64_t length)
{
    bitout *b = calloc(1, sizeof *b);
    if (b) {
        b->to = to;
        b->at = at;
        b->length = length;
    }
    return b;
}

/* The buffer's `n` first bytes put and checksummed, the rest moved down. */
static void put_bytes(bitout *b, uint64_t n)
{
    if (b->put + n > b->length) {
        b->overrun = true;
        n = b->length - b->put;
    }
    if (n) {
        b->to.put(b->to.ctx, b->at + b->put, b->buf, n);
        b->crc = crc32c_update(b->crc, b->buf, (size_t)n);
        b->put += n;
    }
}

void bitout_put(bitout *b, unsigned k, uint64_t v)
{
    format_put(b->buf, b->bit, k, v);
    b->bit += k;
    if (b->bit < 8 * BITOUT_BYTES)
        return;
    uint64_t full = b->bit >> 3;
    uint8_t partial = b->buf[full];
    put_bytes(b, full);
    memset(b->buf, 0, sizeof b->buf);
    b->buf[0] = partial;
    b->bit &= 7;
}

bool bitout_finish(bitout *b, uint32_t *crc)
{
    put_bytes(b, format_pool_bytes(b->bit));
    bool exact = !b->overrun && b->put == b->length;
    *crc = b->crc;
    free(b);
    return exact;
}

void bitout_free(bitout *b)
{
    free(b);
}
