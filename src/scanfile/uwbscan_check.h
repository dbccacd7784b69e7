/* Private to src/scanfile: the checks the uwbscan/1 reader and writer share,
 * so that the writer never produces a file the reader would reject. */
#ifndef UWBSCAN_CHECK_H
#define UWBSCAN_CHECK_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cJSON.h>

#include "uwb/scan.h"

/* Fill err with "NAME: problem" (truncated to errlen; err may be NULL). */
void uwbscan_fail(char *err, size_t errlen, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* 1 if key is one of the header keys the format defines. */
int uwbscan_is_standard_key(const char *key);

/* 1 if s[0..len) is well-formed UTF-8 (no overlongs, surrogates or code
 * points past U+10FFFF); otherwise 0 and *bad_offset = first bad byte. */
int uwbscan_utf8_valid(const unsigned char *s, size_t len, size_t *bad_offset);

/* The first key that occurs twice among object's members, or NULL.
 * Sorted rather than compared pairwise: a 1 MiB header can hold ~10^5 keys. */
const char *uwbscan_duplicate_key(const cJSON *object);

/* Bytes the payload of a positions x samples scan must have; computed in
 * 64 bits so the largest legal scan (16 GiB) cannot overflow. */
uint64_t uwbscan_payload_bytes(int positions, int samples);

/* Every header-level rule of the format, applied to a scan in memory:
 * dimensions, finite numbers, ranges, string encoding and extra_json.
 * The sample values are not looked at (see uwbscan_check_samples). */
int uwbscan_check_fields(const struct uwb_scan *scan, const char *name, char *err, size_t errlen);

/* Every sample finite; message names the first offender as
 * "sample S of position K" (both counted from 0). */
int uwbscan_check_samples(const struct uwb_scan *scan, const char *name, char *err, size_t errlen);

/* Message text for a non-finite binary32 bit pattern's kind. */
const char *uwbscan_nonfinite_kind(uint32_t bits);

#endif
