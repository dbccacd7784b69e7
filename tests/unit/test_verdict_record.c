/* The published verdict record and its JSON: record -> JSON -> record ->
 * JSON gives the same text (a verdict read back from latest.json or
 * verdicts.jsonl says what it said), with figures withheld, every daemon
 * field, and an archive error learnt late; figures are rounded once, as
 * published; lines that are not verdicts are refused naming the key. */
#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

#include "control/reply.h"
#include "unity.h"
#include "uwb/verdict_json.h"
#include "uwb/verdict_record.h"

static struct uwb_verdict_record first, again;

void setUp(void)
{
}

void tearDown(void)
{
}

/* A compared verdict as the evaluation makes it, in metres and seconds. */
static void compared_verdict(struct uwb_verdict *v)
{
    memset(v, 0, sizeof *v);
    v->status = UWB_STATUS_WATCH;
    snprintf(v->scan_id, sizeof v->scan_id, "T7-uwb-20261127T035724.709Z");
    snprintf(v->created, sizeof v->created, "2026-11-27T03:57:24Z");
    v->has_baseline = 1;
    v->current = (struct uwb_edges){.found = 1,
                                    .lower_m = 0.2344712,
                                    .upper_m = 0.3855649,
                                    .center_m = 0.3100181,
                                    .height_m = 0.1510937,
                                    .face_z_m = 0.456149,
                                    .sigma_lower_m = 0.000498,
                                    .sigma_upper_m = 0.000502,
                                    .snr_db = 65.55,
                                    .side_reflector = 1,
                                    .side_reflector_y_m = -0.0123};
    v->baseline =
        (struct uwb_edges){.found = 1, .lower_m = 0.23037, .upper_m = 0.38164, .center_m = 0.306005};
    snprintf(v->baseline_scan_id, sizeof v->baseline_scan_id, "T7-uwb-20261127T035716.630Z");
    v->axial_displacement_m = 0.0040131;
    v->uncertainty_m = 0.000104;
    v->height_change_m = -0.000184;
    v->height_change_uncertainty_m = 0.000341;
    v->has_direct_coupling = 1;
    v->direct_coupling_s = 62.54e-12;
    v->has_direct_coupling_shift = 1;
    v->direct_coupling_shift_s = -0.00001e-12; /* rounds to -0: printed 0 */
    v->n_images = 2;
    snprintf(v->images[0], sizeof v->images[0], "/var/lib/uwbd/archive/a-migrated.png");
    snprintf(v->images[1], sizeof v->images[1], "/var/lib/uwbd/archive/a-bscan.png");
}

/* record -> JSON -> record -> JSON: the two texts equal; returns the first (malloc'd). */
static char *assert_round_trip(const struct uwb_verdict_record *r)
{
    char *text = uwb_record_to_json(r);
    TEST_ASSERT_NOT_NULL(text);
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(text, &again, err, sizeof err), err);
    char *back = uwb_record_to_json(&again);
    TEST_ASSERT_NOT_NULL(back);
    TEST_ASSERT_EQUAL_STRING(text, back);
    free(back);
    return text;
}

static void test_compared_verdict_round_trips_with_its_figures_as_published(void)
{
    struct uwb_verdict v;
    compared_verdict(&v);
    uwb_record_from_verdict(&first, &v);
    TEST_ASSERT_TRUE(first.has_displacement);
    TEST_ASSERT_EQUAL_DOUBLE(4.01, first.axial_displacement_mm);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, first.edge_uncertainty_mm);
    TEST_ASSERT_EQUAL_DOUBLE(65.6, first.snr_db);
    char *text = assert_round_trip(&first);
    /* the evaluation's own JSON is the record's */
    char *direct = uwb_verdict_to_json(&v);
    TEST_ASSERT_EQUAL_STRING(direct, text);
    TEST_ASSERT_NOT_NULL(strstr(text, "\"axial_displacement_mm\":4.01,\"uncertainty_mm\":0.1,"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"direct_coupling_shift_ps\":0,"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"side_reflector_mm\":-12.3,"));
    TEST_ASSERT_EQUAL_DOUBLE(4.01, again.axial_displacement_mm);
    TEST_ASSERT_EQUAL_STRING("T7-uwb-20261127T035716.630Z", again.baseline_scan_id);
    TEST_ASSERT_EQUAL_INT(2, again.n_images);
    free(direct);
    free(text);
}

static void test_withheld_height_change_and_inconclusive_round_trip(void)
{
    struct uwb_verdict v;
    compared_verdict(&v);
    snprintf(v.height_change_withheld, sizeof v.height_change_withheld, "an edge is not sharp enough");
    uwb_record_from_verdict(&first, &v);
    char *text = assert_round_trip(&first);
    TEST_ASSERT_NULL(strstr(text, "height_change_mm"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"height_change_withheld\":\"an edge is not sharp enough\""));
    TEST_ASSERT_FALSE(again.has_height_change);
    free(text);

    v.status = UWB_STATUS_INCONCLUSIVE;
    snprintf(v.reason, sizeof v.reason, "no shift maps the baseline's face profile onto this scan's");
    uwb_record_from_verdict(&first, &v);
    text = assert_round_trip(&first);
    TEST_ASSERT_NULL(strstr(text, "axial_displacement_mm"));
    TEST_ASSERT_NULL(strstr(text, "height_change_withheld"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"baseline\":{"));
    TEST_ASSERT_FALSE(again.has_displacement);
    free(text);
}

/* The radial change measured, its tilt given or withheld with why: never
 * a tilt_mm of 0 for a lean that could not be read. */
static void test_a_withheld_tilt_round_trips_as_its_reason(void)
{
    struct uwb_verdict v;
    compared_verdict(&v);
    v.radial = (struct uwb_radial_verdict){.measured = 1,
                                           .status = UWB_STATUS_ALARM,
                                           .max_change_m = 0.00845,
                                           .at_m = 0.3411,
                                           .uncertainty_m = 0.00157,
                                           .tilt_m = 0.0012,
                                           .tilt_uncertainty_m = 0.00031};
    uwb_record_from_verdict(&first, &v);
    char *text = assert_round_trip(&first);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(text, "\"uncertainty_mm\":1.57,\"tilt_mm\":1.2,\"tilt_uncertainty_mm\":0.31}"), text);
    TEST_ASSERT_TRUE(again.radial_has_tilt);
    TEST_ASSERT_EQUAL_DOUBLE(1.2, again.radial_tilt_mm);
    TEST_ASSERT_TRUE(again.radial_has_tilt_uncertainty);
    TEST_ASSERT_EQUAL_DOUBLE(0.31, again.radial_tilt_uncertainty_mm);
    free(text);

    snprintf(v.radial.tilt_withheld, sizeof v.radial.tilt_withheld, "the change reaches the face's end");
    v.radial.tilt_m = 0.0;
    v.radial.tilt_uncertainty_m = 0.0;
    uwb_record_from_verdict(&first, &v);
    text = assert_round_trip(&first);
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "tilt_mm"), text);
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "tilt_uncertainty_mm"), text);
    TEST_ASSERT_FALSE(again.radial_has_tilt_uncertainty);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"tilt_withheld\":\"the change reaches the face's end\""),
                                 text);
    TEST_ASSERT_TRUE(again.radial_measured);
    TEST_ASSERT_FALSE(again.radial_has_tilt);
    TEST_ASSERT_EQUAL_STRING("the change reaches the face's end", again.radial_tilt_withheld);
    TEST_ASSERT_EQUAL_DOUBLE(8.45, again.radial_max_change_mm);
    free(text);
}

/* A record from before the tilt carried its sigma still reads: the tilt
 * given, its sigma absent (not 0). */
static void test_a_tilt_without_its_sigma_still_reads(void)
{
    char err[256];
    const char *line = "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"S1\",\"radial\":{\"status\":"
                       "\"ok\",\"max_change_mm\":0.4,"
                       "\"at_mm\":300,\"uncertainty_mm\":0.5,\"tilt_mm\":-1.5}}";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(line, &again, err, sizeof err), err);
    TEST_ASSERT_TRUE(again.radial_has_tilt);
    TEST_ASSERT_EQUAL_DOUBLE(-1.5, again.radial_tilt_mm);
    TEST_ASSERT_FALSE(again.radial_has_tilt_uncertainty);
    char *text = uwb_record_to_json(&again);
    TEST_ASSERT_NOT_NULL(text);
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "tilt_uncertainty_mm"), text);
    free(text);
}

static void test_error_verdict_with_no_figures_round_trips(void)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.status = UWB_STATUS_ERROR;
    snprintf(v.reason, sizeof v.reason, "fault: the baseline file is damaged");
    snprintf(v.fault, sizeof v.fault, "baseline");
    uwb_record_from_verdict(&first, &v);
    char *text = assert_round_trip(&first);
    TEST_ASSERT_EQUAL_STRING(
        "{\"class\":\"VERDICT\",\"status\":\"error\",\"reason\":\"fault: the baseline file is damaged\","
        "\"fault\":\"baseline\",\"images\":[]}",
        text);
    TEST_ASSERT_EQUAL_STRING("baseline", again.fault);
    free(text);
}

static void test_daemon_fields_round_trip_in_their_order(void)
{
    struct uwb_verdict v;
    compared_verdict(&v);
    uwb_record_from_verdict(&first, &v);
    struct uwb_verdict_cycle *c = &first.cycle;
    c->has_scan_file = 1;
    snprintf(c->scan_file, sizeof c->scan_file, "/var/lib/uwbd/archive/a.uwbscan");
    c->has_baseline_set = 1;
    c->baseline_set = 1;
    snprintf(c->baseline_note, sizeof c->baseline_note, "replaced a baseline that failed its check");
    c->pulses_per_position = 64;
    c->acquisitions = 2;
    snprintf(c->reacquire_note, sizeof c->reacquire_note, "the budget is spent");
    c->baseline_scans = 3;
    c->has_baseline_repeatability = 1;
    c->baseline_repeatability_mm = 0.042;
    snprintf(c->asset_id, sizeof c->asset_id, "T7");
    snprintf(c->trigger, sizeof c->trigger, "event");
    snprintf(c->clock_warning, sizeof c->clock_warning, "the clock went back 3 s");
    snprintf(c->record_error, sizeof c->record_error, "verdicts.jsonl: No space left on device");
    char *text = assert_round_trip(&first);
    TEST_ASSERT_NOT_NULL(
        strstr(text, "\"images\":[\"/var/lib/uwbd/archive/a-migrated.png\","
                     "\"/var/lib/uwbd/archive/a-bscan.png\"],"
                     "\"scan_file\":\"/var/lib/uwbd/archive/a.uwbscan\",\"baseline_set\":true,"
                     "\"baseline_note\":\"replaced a baseline that failed its check\","
                     "\"pulses_per_position\":64,\"acquisitions\":2,"
                     "\"reacquire_note\":\"the budget is spent\",\"baseline_scans\":3,"
                     "\"baseline_repeatability_mm\":0.042,\"asset_id\":\"T7\",\"trigger\":\"event\","
                     "\"clock_warning\":\"the clock went back 3 s\","
                     "\"record_error\":\"verdicts.jsonl: No space left on device\"}"));
    TEST_ASSERT_EQUAL_INT(64, again.cycle.pulses_per_position);
    TEST_ASSERT_EQUAL_STRING("event", again.cycle.trigger);
    free(text);

    /* An archive error learnt after the verdict was first printed comes after the clock warning. */
    snprintf(c->archive_error, sizeof c->archive_error, "archive: read-only file system");
    c->archive_error_late = 1;
    text = assert_round_trip(&first);
    TEST_ASSERT_NOT_NULL(strstr(text, "\"clock_warning\":\"the clock went back 3 s\","
                                      "\"archive_error\":\"archive: read-only file system\","));
    TEST_ASSERT_TRUE(again.cycle.archive_error_late);
    free(text);
    c->archive_error_late = 0;
    text = assert_round_trip(&first);
    TEST_ASSERT_NOT_NULL(strstr(text, "\"trigger\":\"event\",\"archive_error\":"));
    TEST_ASSERT_FALSE(again.cycle.archive_error_late);
    free(text);
}

static void test_lines_that_are_not_verdicts_are_refused_naming_the_key(void)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT(-1, uwb_record_from_json("not json", &again, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(
        -1, uwb_record_from_json("{\"class\":\"STATUS\",\"status\":\"ok\"}", &again, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("verdict: not a VERDICT object", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_record_from_json("{\"status\":\"ok\"}", &again, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(
        -1, uwb_record_from_json("{\"class\":\"VERDICT\",\"status\":\"fine\"}", &again, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "`status`"));
    TEST_ASSERT_EQUAL_INT(
        -1, uwb_record_from_json("{\"class\":\"VERDICT\",\"status\":\"ok\",\"axial_displacement_mm\":\"4\"}",
                                 &again, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("verdict: key `axial_displacement_mm`: not a number", err);
    TEST_ASSERT_EQUAL_INT(
        -1, uwb_record_from_json(
                "{\"class\":\"VERDICT\",\"status\":\"error\",\"fault\":\"a fault name far too long\"}",
                &again, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("verdict: key `fault`: too long", err);
    TEST_ASSERT_EQUAL_INT(-1, uwb_record_from_json("{\"class\":\"VERDICT\",\"status\":\"ok\",\"images\":[1]}",
                                                   &again, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "`images`"));
    /* unknown keys (a newer uwbd's) are passed over */
    TEST_ASSERT_EQUAL_INT(0, uwb_record_from_json("{\"class\":\"VERDICT\",\"status\":\"ok\",\"radial_mm\":1}",
                                                  &again, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_STATUS_OK, again.status);
}

static void test_summary_keeps_the_story_fields_in_order(void)
{
    struct uwb_verdict v;
    compared_verdict(&v);
    uwb_record_from_verdict(&first, &v);
    first.cycle.has_baseline_set = 1;
    cJSON *s = uwb_record_summary(&first);
    char *text = cJSON_PrintUnformatted(s);
    TEST_ASSERT_EQUAL_STRING(
        "{\"scan_id\":\"T7-uwb-20261127T035724.709Z\",\"created\":\"2026-11-27T03:57:24Z\","
        "\"status\":\"watch\",\"axial_displacement_mm\":4.01,\"uncertainty_mm\":0.1,"
        "\"center_mm\":310.02,\"height_change_mm\":-0.18,\"baseline_set\":false}",
        text);
    free(text);
    cJSON_Delete(s);
}

static void test_history_lists_verdicts_and_counts_other_lines_unreadable(void)
{
    char *lines[] = {
        "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"a\",\"axial_displacement_mm\":0.5,"
        "\"uncertainty_mm\":0.1,\"images\":[],\"scan_file\":\"/x\"}",
        "{\"n\":2}", "{\"class\":\"VERDICT\",\"status\":\"edges\",\"scan_id\":\"c\"}"};
    char *reply = uwbd_reply_history(lines, 3, 10, 1);
    TEST_ASSERT_EQUAL_STRING(
        "{\"class\":\"HISTORY\",\"requested\":10,\"count\":2,\"unreadable_lines\":2,"
        "\"verdicts\":[{\"scan_id\":\"a\",\"status\":\"ok\",\"axial_displacement_mm\":0.5,"
        "\"uncertainty_mm\":0.1},{\"scan_id\":\"c\",\"status\":\"edges\"}]}",
        reply);
    free(reply);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_compared_verdict_round_trips_with_its_figures_as_published);
    RUN_TEST(test_withheld_height_change_and_inconclusive_round_trip);
    RUN_TEST(test_a_withheld_tilt_round_trips_as_its_reason);
    RUN_TEST(test_a_tilt_without_its_sigma_still_reads);
    RUN_TEST(test_error_verdict_with_no_figures_round_trips);
    RUN_TEST(test_daemon_fields_round_trip_in_their_order);
    RUN_TEST(test_lines_that_are_not_verdicts_are_refused_naming_the_key);
    RUN_TEST(test_summary_keeps_the_story_fields_in_order);
    RUN_TEST(test_history_lists_verdicts_and_counts_other_lines_unreadable);
    return UNITY_END();
}
