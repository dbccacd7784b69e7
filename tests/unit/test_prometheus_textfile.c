/* The Prometheus textfile: the exposition text node_exporter's textfile
 * collector parses (HELP/TYPE before samples, one label set per sample,
 * base units), written whole or not at all, readable by another user. */
#include "unity.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scratch_support.h"
#include "integrations/prometheus_textfile.h"
#include "uwb/verdict_json.h"

static char dir[256];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "prom");
}

void tearDown(void)
{
    chmod(dir, 0700);
    scratch_remove_tree(dir);
}

static struct uwbd_prometheus_metrics alarm_metrics(void)
{
    struct uwbd_prometheus_metrics m = {
        .asset_id = "T3-north",
        .has_verdict = 1,
        .status = uwbd_prometheus_status_index("alarm"),
        .figures = {.has_displacement = 1,
                    .axial_displacement_mm = 7.97,
                    .uncertainty_mm = 0.1,
                    .has_edges = 1,
                    .lower_edge_mm = 239.73,
                    .upper_edge_mm = 388.22},
        .created_s = 1795000000,
        .has_duration = 1,
        .scan_duration_s = 5.25,
        .event_scans = 1,
        .has_contacts = 1,
        .contact = {1, 1, 1},
    };
    m.verdicts[uwbd_prometheus_status_index("ok")] = 3;
    m.verdicts[uwbd_prometheus_status_index("alarm")] = 1;
    return m;
}

/* `line` is one whole line of text. */
static void expect_line(const char *text, const char *line)
{
    size_t n = strlen(line);
    for (const char *p = strstr(text, line); p; p = strstr(p + 1, line))
        if ((p == text || p[-1] == '\n') && (p[n] == '\n' || p[n] == '\0'))
            return;
    TEST_FAIL_MESSAGE(line);
}

static void test_the_latest_verdict_in_base_units(void)
{
    struct uwbd_prometheus_metrics m = alarm_metrics();
    char *text = uwbd_prometheus_text(&m);
    TEST_ASSERT_NOT_NULL(text);
    expect_line(text, "# TYPE uwbd_axial_displacement_meters gauge");
    expect_line(text, "uwbd_axial_displacement_meters{asset_id=\"T3-north\"} 0.00797");
    expect_line(text, "uwbd_axial_displacement_uncertainty_meters{asset_id=\"T3-north\"} 0.0001");
    expect_line(text, "uwbd_status{asset_id=\"T3-north\",status=\"alarm\"} 1");
    expect_line(text, "uwbd_status{asset_id=\"T3-north\",status=\"ok\"} 0");
    expect_line(text, "uwbd_edge_meters{asset_id=\"T3-north\",edge=\"lower\"} 0.23973");
    expect_line(text, "uwbd_scan_duration_seconds{asset_id=\"T3-north\"} 5.25");
    expect_line(text, "uwbd_last_verdict_timestamp_seconds{asset_id=\"T3-north\"} 1795000000");
    expect_line(text, "# TYPE uwbd_verdicts_total counter");
    expect_line(text, "uwbd_verdicts_total{asset_id=\"T3-north\",status=\"ok\"} 3");
    expect_line(text, "uwbd_verdicts_total{asset_id=\"T3-north\",status=\"error\"} 0");
    expect_line(text, "uwbd_event_scans_total{asset_id=\"T3-north\"} 1");
    expect_line(text, "uwbd_contact_energised{asset_id=\"T3-north\",contact=\"fault\"} 1");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "height_change"), "no height change given, none written");
    /* Every sample's metric has its TYPE line before it. */
    char *copy = strdup(text);
    char seen_types[2048] = "";
    for (char *line = strtok(copy, "\n"); line; line = strtok(NULL, "\n")) {
        char name[128];
        if (sscanf(line, "# TYPE %127s", name) == 1) {
            strcat(seen_types, name);
            strcat(seen_types, " ");
        } else if (line[0] != '#') {
            TEST_ASSERT_EQUAL_INT(1, sscanf(line, "%127[^{]", name));
            strcat(name, " ");
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(seen_types, name), line);
        }
    }
    free(copy);
    free(text);
}

static void test_no_verdict_yet_gives_only_counters(void)
{
    struct uwbd_prometheus_metrics m = {.asset_id = "T1"};
    char *text = uwbd_prometheus_text(&m);
    TEST_ASSERT_NOT_NULL(text);
    TEST_ASSERT_NULL(strstr(text, "uwbd_status{"));
    TEST_ASSERT_NULL(strstr(text, "uwbd_axial_displacement_meters{"));
    expect_line(text, "uwbd_verdicts_total{asset_id=\"T1\",status=\"alarm\"} 0");
    free(text);
}

/* The textfile's figures from a verdict line, as the daemon takes them from its record. */
static char *text_of_verdict(const char *line)
{
    static struct uwb_verdict_record record;
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(line, &record, err, sizeof err), err);
    struct uwbd_prometheus_metrics m = {.asset_id = "T1"};
    uwbd_prometheus_from_record(&m, &record);
    char *text = uwbd_prometheus_text(&m);
    TEST_ASSERT_NOT_NULL(text);
    return text;
}

/* The radial change in metres (+ toward the antenna), its sigma, height and
 * tilt; its status as uwbd_status is; withheld figures absent, as the
 * axial figure's are. */
static void test_the_radial_change_in_base_units(void)
{
    char *text = text_of_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"radial\":{\"status\":\"alarm\",\"max_change_mm\":"
        "-5.75,\"at_mm\":359.59,\"from_mm\":332.59,\"to_mm\":384.59,\"uncertainty_mm\":0.46,\"tilt_mm\":2,"
        "\"tilt_uncertainty_mm\":0.31}}");
    expect_line(text, "# TYPE uwbd_radial_status gauge");
    expect_line(text, "uwbd_radial_status{asset_id=\"T1\",status=\"alarm\"} 1");
    expect_line(text, "uwbd_radial_status{asset_id=\"T1\",status=\"ok\"} 0");
    expect_line(text, "# TYPE uwbd_radial_max_change_meters gauge");
    expect_line(text, "uwbd_radial_max_change_meters{asset_id=\"T1\"} -0.00575");
    expect_line(text, "uwbd_radial_max_change_uncertainty_meters{asset_id=\"T1\"} 0.00046");
    expect_line(text, "uwbd_radial_max_change_height_meters{asset_id=\"T1\"} 0.35959");
    expect_line(text, "uwbd_radial_tilt_meters{asset_id=\"T1\"} 0.002");
    expect_line(text, "# TYPE uwbd_radial_tilt_uncertainty_meters gauge");
    expect_line(text, "uwbd_radial_tilt_uncertainty_meters{asset_id=\"T1\"} 0.00031");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_axial_displacement_meters{"), "the axial figure withheld");
    free(text);

    /* A record from before the tilt's sigma: the tilt, no sigma metric. */
    text = text_of_verdict("{\"class\":\"VERDICT\",\"status\":\"ok\",\"radial\":{\"status\":\"ok\","
                           "\"max_change_mm\":0.4,\"at_mm\":300,\"uncertainty_mm\":0.5,\"tilt_mm\":-1.5}}");
    expect_line(text, "uwbd_radial_tilt_meters{asset_id=\"T1\"} -0.0015");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_radial_tilt_uncertainty"), "no sigma: no sigma metric");
    free(text);

    /* Measured, the tilt withheld (a change at the face's end): the change given, no tilt metric. */
    text = text_of_verdict("{\"class\":\"VERDICT\",\"status\":\"alarm\",\"radial\":{\"status\":\"alarm\","
                           "\"max_change_mm\":8.45,\"at_mm\":341,\"uncertainty_mm\":1.57,"
                           "\"tilt_withheld\":\"the change reaches the face's end\"}}");
    expect_line(text, "uwbd_radial_max_change_meters{asset_id=\"T1\"} 0.00845");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_radial_tilt"), "tilt withheld: no tilt metric");
    free(text);

    text = text_of_verdict("{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"radial\":{\"status\":"
                           "\"inconclusive\",\"withheld\":\"the face's range was not compared\"}}");
    expect_line(text, "uwbd_radial_status{asset_id=\"T1\",status=\"inconclusive\"} 1");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_radial_max_change"), "withheld: no figure");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_radial_tilt"), "withheld: no tilt");
    free(text);

    text = text_of_verdict("{\"class\":\"VERDICT\",\"status\":\"ok\",\"axial_displacement_mm\":0.12,"
                           "\"uncertainty_mm\":0.1}");
    expect_line(text, "uwbd_axial_displacement_meters{asset_id=\"T1\"} 0.00012");
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "uwbd_radial"), "no radial object: no radial metric");
    free(text);
}

static int temporaries_in(const char *path)
{
    DIR *d = opendir(path);
    TEST_ASSERT_NOT_NULL(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += strncmp(e->d_name, ".uwbd-tmp.", 10) == 0;
    closedir(d);
    return n;
}

static void test_written_atomically_and_readable(void)
{
    char path[300], err[512];
    snprintf(path, sizeof path, "%s/uwbd.prom", dir);
    struct uwbd_prometheus_metrics m = alarm_metrics();
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_prometheus_write(path, &m, err, sizeof err), err);
    char *text = uwbd_prometheus_text(&m), *file = scratch_slurp(path, NULL);
    TEST_ASSERT_EQUAL_STRING(text, file);
    free(text);
    free(file);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(path, &st));
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0644, st.st_mode & 0777, "node_exporter reads it as another user");
    TEST_ASSERT_EQUAL_INT(0, temporaries_in(dir));

    /* A directory it may not write to: an error naming the file, the old one whole. */
    if (geteuid() != 0) {
        chmod(dir, 0500);
        m.status = uwbd_prometheus_status_index("ok");
        TEST_ASSERT_EQUAL_INT(-1, uwbd_prometheus_write(path, &m, err, sizeof err));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "uwbd.prom"), err);
        chmod(dir, 0700);
        file = scratch_slurp(path, NULL);
        TEST_ASSERT_NOT_NULL(strstr(file, "status=\"alarm\"} 1"));
        free(file);
    }
    char missing[320];
    snprintf(missing, sizeof missing, "%s/no-such-dir/uwbd.prom", dir);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_prometheus_write(missing, &m, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-dir"), err);
    TEST_ASSERT_EQUAL_INT(0, temporaries_in(dir));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_the_latest_verdict_in_base_units);
    RUN_TEST(test_no_verdict_yet_gives_only_counters);
    RUN_TEST(test_the_radial_change_in_base_units);
    RUN_TEST(test_written_atomically_and_readable);
    return UNITY_END();
}
