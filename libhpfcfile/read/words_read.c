/*
 * The fixed word code of spec/hpfc-format.md §5.2.3 read (words.h): the paper
 * layout's word slots decoded into symbols.
 */
#include "words.h"

#include "hpfc.h"

int word_decode_code(const format_bits *pool, uint64_t off, uint32_t word_bits, char *buf,
                     size_t cap, size_t *len)
{
    uint64_t pos = 0, window = 0;
    unsigned have = 0, plus = 0; /* `have` bits of the slot are left-aligned in window */
    size_t n = 0;
    while (plus < 4) {
        if (have < 4) { /* in windows of up to 56 bits */
            uint64_t left = word_bits - pos;
            have = left < 56 ? (unsigned)left : 56;
            window = format_peek(pool, off + pos, have);
            if (have == 0)
                return HPFC_E_CORRUPT; /* no fourth '+' in the slot */
        }
        char c;
        if (!(window >> 63)) {
            c = '+';
            plus++;
            window <<= 1;
            have -= 1;
            pos += 1;
        } else {
            unsigned code = (unsigned)(window >> 60);
            if (have < 4 || code >= FORMAT_CODE_RESERVED_MIN)
                return HPFC_E_CORRUPT; /* a code cut by the slot's end, or reserved */
            c = format_code_symbol(code);
            window <<= 4;
            have -= 4;
            pos += 4;
        }
        if (buf && n < cap)
            buf[n] = c;
        n++;
    }
    *len = n;
    return buf && n > cap ? HPFC_E_BUFFER_SMALL : HPFC_OK;
}

