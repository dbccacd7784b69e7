/* Mutating digitiser byte streams past their CRCs: after libFuzzer's own
 * mutation, most frames carry a CRC that no longer matches, and a decoder
 * that drops them is all the fuzzer would ever see. This rewrites the
 * header and frame CRCs of the frames in the buffer (layout in
 * board/digitiser-protocol.md) for three mutations in four, so the code
 * behind the CRC checks meets mutated frames too while the checks keep
 * meeting bad CRCs. */
#include <string.h>
#include <zlib.h>

#include "fuzz_harness.h"
#include "uwb/frame.h"

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t crc_of(const uint8_t *p, size_t n)
{
    return (uint32_t)crc32(crc32(0L, Z_NULL, 0), p, (uInt)n);
}

void fuzz_fix_frame_crcs(uint8_t *data, size_t size, unsigned seed)
{
    if (seed % 4 == 0)
        return;
    for (size_t at = 0; at + UWB_FRAME_HEADER_BYTES <= size; at++) {
        if (memcmp(data + at, uwb_frame_sync, UWB_FRAME_SYNC_BYTES) != 0)
            continue;
        uint8_t *h = data + at;
        put_u32(h + 16, crc_of(h, 16));
        uint32_t length = get_u32(h + 12);
        if (length > UWB_FRAME_MAX_PAYLOAD || uwb_frame_size(length) > size - at)
            continue; /* a truncated frame stays truncated */
        size_t body = UWB_FRAME_HEADER_BYTES + length;
        put_u32(h + body, crc_of(h, body));
        at += body + UWB_FRAME_TRAILER_BYTES - 1;
    }
}
