/* Fuzzing the uwbscan/1 reader (uwbscan_parse): any bytes are refused
 * with a message or read into a scan that obeys the format; an accepted
 * scan written back (uwbscan_serialise) reads again as the same scan and
 * serialises to the same bytes, so reader and writer agree on everything
 * the reader lets through. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/scan.h"

static int same_text(const char *a, const char *b)
{
    return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

static int check_scan(const struct uwb_scan *s, char *why, size_t whylen)
{
    if (s->positions < 1 || s->positions > UWBSCAN_MAX_POSITIONS || s->samples < 1 ||
        s->samples > UWBSCAN_MAX_SAMPLES)
        return fuzz_broken(why, whylen, "accepted %d x %d, outside the format's limits", s->positions,
                           s->samples);
    if (!s->antenna_y_m || !s->data)
        return fuzz_broken(why, whylen, "accepted without antenna heights or samples");
    if (!(s->sample_interval_s > 0) || !isfinite(s->sample_interval_s) || !isfinite(s->t0_s) ||
        !(s->eps_r >= 1) || !isfinite(s->eps_r))
        return fuzz_broken(why, whylen, "accepted sample_interval_s %g, t0_s %g, eps_r %g",
                           s->sample_interval_s, s->t0_s, s->eps_r);
    if (s->has_target_z && !(s->target_z_m[0] < s->target_z_m[1]))
        return fuzz_broken(why, whylen, "accepted target_z_m [%g, %g]", s->target_z_m[0], s->target_z_m[1]);
    for (int k = 0; k < s->positions; k++)
        if (!isfinite(s->antenna_y_m[k]))
            return fuzz_broken(why, whylen, "accepted a non-finite antenna_y_m[%d]", k);
    size_t count = (size_t)s->positions * (size_t)s->samples;
    for (size_t i = 0; i < count; i++)
        if (!isfinite(s->data[i]))
            return fuzz_broken(why, whylen, "accepted a non-finite sample %zu", i);
    return FUZZ_ACCEPTED;
}

static int same_scan(const struct uwb_scan *a, const struct uwb_scan *b)
{
    size_t count = (size_t)a->positions * (size_t)a->samples;
    return a->positions == b->positions && a->samples == b->samples &&
           a->sample_interval_s == b->sample_interval_s && a->t0_s == b->t0_s &&
           memcmp(a->antenna_y_m, b->antenna_y_m, (size_t)a->positions * sizeof *a->antenna_y_m) == 0 &&
           memcmp(a->tx_m, b->tx_m, sizeof a->tx_m) == 0 && memcmp(a->rx_m, b->rx_m, sizeof a->rx_m) == 0 &&
           a->eps_r == b->eps_r && a->has_target_z == b->has_target_z &&
           (!a->has_target_z || memcmp(a->target_z_m, b->target_z_m, sizeof a->target_z_m) == 0) &&
           a->stack == b->stack && same_text(a->created, b->created) && same_text(a->scan_id, b->scan_id) &&
           same_text(a->source, b->source) && same_text(a->comment, b->comment) &&
           same_text(a->extra_json, b->extra_json) && memcmp(a->data, b->data, count * sizeof *a->data) == 0;
}

/* Write the scan, read it back, write it again. */
static int check_round_trip(const struct uwb_scan *scan, char *why, size_t whylen)
{
    char err[512] = "";
    unsigned char *first = NULL, *second = NULL;
    size_t first_len = 0, second_len = 0;
    struct uwb_scan again;
    memset(&again, 0, sizeof again);
    int rc;
    if (uwbscan_serialise(scan, &first, &first_len, err, sizeof err) != 0)
        rc = fuzz_broken(why, whylen, "an accepted scan does not serialise: %s", err);
    else if (uwbscan_parse(first, first_len, "rewritten", &again, err, sizeof err) != 0)
        rc = fuzz_broken(why, whylen, "an accepted scan, rewritten, is refused: %s", err);
    else if (!same_scan(scan, &again))
        rc = fuzz_broken(why, whylen, "an accepted scan, rewritten and read again, differs");
    else if (uwbscan_serialise(&again, &second, &second_len, err, sizeof err) != 0)
        rc = fuzz_broken(why, whylen, "a rewritten scan does not serialise: %s", err);
    else if (first_len != second_len || memcmp(first, second, first_len) != 0)
        rc = fuzz_broken(why, whylen, "rewriting a rewritten scan changes its bytes");
    else
        rc = FUZZ_ACCEPTED;
    uwb_scan_free(&again);
    free(first);
    free(second);
    return rc;
}

int fuzz_scan_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    struct uwb_scan scan;
    why[0] = '\0';
    if (uwbscan_parse(data, size, "fuzz.uwbscan", &scan, why, whylen) != 0) {
        if (!why[0])
            return fuzz_broken(why, whylen, "refused without a message");
        if (scan.data || scan.antenna_y_m || scan.extra_json || scan.created || scan.scan_id || scan.source ||
            scan.comment)
            return fuzz_broken(why, whylen, "refused but left memory in the scan");
        return FUZZ_REJECTED;
    }
    int rc = check_scan(&scan, why, whylen);
    if (rc == FUZZ_ACCEPTED)
        rc = check_round_trip(&scan, why, whylen);
    uwb_scan_free(&scan);
    return rc;
}

UWB_FUZZ_TARGET(fuzz_scan_input)
