/* The uwbsim command line, driven in-process. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scratch_support.h"
#include "unity.h"
#include "uwbsim/cli.h"
#include "uwbsim/uwbsim.h"

static char dir[64];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "sim-cli");
}

void tearDown(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, scratch_remove_tree(dir), dir);
}

/* Run the CLI; return its status, its stdout and stderr (malloc'd). */
static int run(char **argv, char **out, char **errtext)
{
    int argc = 0;
    while (argv[argc])
        argc++;
    FILE *o = tmpfile(), *e = tmpfile();
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_NOT_NULL(e);
    int rc = uwbsim_cli(argc, argv, o, e);
    FILE *f[2] = {o, e};
    char **dst[2] = {out, errtext};
    for (int i = 0; i < 2; i++) {
        long n = ftell(f[i]);
        rewind(f[i]);
        *dst[i] = calloc((size_t)n + 1, 1);
        TEST_ASSERT_EQUAL_UINT64((uint64_t)n, (uint64_t)fread(*dst[i], 1, (size_t)n, f[i]));
        fclose(f[i]);
    }
    return rc;
}

static void test_help_lists_every_parameter_with_unit_and_default(void)
{
    char *argv[] = {"uwbsim", "--help", NULL}, *out, *err;
    TEST_ASSERT_EQUAL_INT(0, run(argv, &out, &err));
    size_t n;
    const struct sim_param *all = sim_params(&n);
    for (size_t i = 0; i < n; i++) {
        char opt[160], def[160];
        snprintf(opt, sizeof opt, "--%s ", all[i].name);
        for (char *c = opt; *c; c++)
            if (*c == '_')
                *c = '-';
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, opt), opt);
        /* the option's own paragraph states its default (and unit) */
        const char *para = strstr(out, opt);
        const char *next = strstr(para + 2, "\n  --");
        size_t len = next ? (size_t)(next - para) : strlen(para);
        char *chunk = strndup(para, len);
        snprintf(def, sizeof def, "default %s", all[i].def[0] ? all[i].def : "empty");
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(chunk, def), opt);
        if (all[i].unit[0]) {
            char unit[64];
            snprintf(unit, sizeof unit, "[%s;", all[i].unit);
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(chunk, unit), opt);
        }
        free(chunk);
    }
    TEST_ASSERT_NOT_NULL(strstr(out, "--seed"));
    TEST_ASSERT_NOT_NULL(strstr(out, "--truth"));
    free(out);
    free(err);
}

static void test_markdown_table_has_a_row_per_parameter(void)
{
    char *argv[] = {"uwbsim", "--params-markdown", NULL}, *out, *err;
    TEST_ASSERT_EQUAL_INT(0, run(argv, &out, &err));
    size_t n, rows = 0;
    const struct sim_param *all = sim_params(&n);
    for (const char *p = out; (p = strstr(p, "\n| `")); p++)
        rows++;
    TEST_ASSERT_EQUAL_UINT64((uint64_t)n, (uint64_t)rows);
    for (size_t i = 0; i < n; i++) {
        char key[160];
        snprintf(key, sizeof key, "| `%s` ", all[i].name);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, key), key);
    }
    free(out);
    free(err);
}

static void test_writes_scan_and_truth(void)
{
    char scan[128], truth[128], seedtext[] = "3";
    snprintf(scan, sizeof scan, "%s/a.uwbscan", dir);
    snprintf(truth, sizeof truth, "%s/a.truth.json", dir);
    char *argv[] = {"uwbsim",
                    "--samples",
                    "100",
                    "--scene",
                    "tools/uwbsim/scenes/fdtd2d-paper.json",
                    "--displacement-m=0.01",
                    "--seed",
                    seedtext,
                    "-o",
                    scan,
                    "--truth",
                    truth,
                    NULL};
    char *out, *err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run(argv, &out, &err), err);
    struct uwb_scan s;
    char msg[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_read_file(scan, &s, msg, sizeof msg), msg);
    TEST_ASSERT_EQUAL_INT(21, s.positions);
    TEST_ASSERT_EQUAL_INT(1697, s.samples); /* the scene file came after --samples */
    TEST_ASSERT_EQUAL_DOUBLE(1.0, s.eps_r);
    TEST_ASSERT_NOT_NULL(strstr(s.source, "2-D"));
    /* byte-identical to the library's own scan for the same scene and seed */
    struct sim_scene sc;
    sim_scene_default(&sc);
    TEST_ASSERT_EQUAL_INT(0,
                          sim_scene_load_json("tools/uwbsim/scenes/fdtd2d-paper.json", &sc, msg, sizeof msg));
    sc.displacement_m = 0.01;
    struct uwb_scan lib;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 3, &lib, msg, sizeof msg), msg);
    TEST_ASSERT_EQUAL_MEMORY(lib.data, s.data, sizeof(float) * (size_t)s.positions * s.samples);
    uwb_scan_free(&lib);
    uwb_scan_free(&s);

    FILE *f = fopen(truth, "r");
    TEST_ASSERT_NOT_NULL(f);
    char text[2048];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    cJSON *o = cJSON_Parse(text);
    TEST_ASSERT_NOT_NULL(o);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.24, cJSON_GetObjectItemCaseSensitive(o, "y1_m")->valuedouble);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 10.0,
                              cJSON_GetObjectItemCaseSensitive(o, "displacement_mm")->valuedouble);
    cJSON_Delete(o);
    free(out);
    free(err);
}

static void expect_usage_error(char **argv, const char *needle)
{
    char *out, *err;
    TEST_ASSERT_EQUAL_INT(2, run(argv, &out, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, needle), err);
    free(out);
    free(err);
}

static void test_usage_errors(void)
{
    char scan[128], bad[128];
    snprintf(scan, sizeof scan, "%s/x.uwbscan", dir);
    snprintf(bad, sizeof bad, "%s/bad.json", dir);
    FILE *f = fopen(bad, "w");
    TEST_ASSERT_NOT_NULL(f);
    fputs("{\"disks\": 6, \"colour\": \"red\"}\n", f);
    fclose(f);
    char *a1[] = {"uwbsim", "--snr", "3", "-o", scan, NULL};
    expect_usage_error(a1, "snr");
    char *a2[] = {"uwbsim", "--eps-r", "oil", "-o", scan, NULL};
    expect_usage_error(a2, "eps_r");
    char *a3[] = {"uwbsim", "--seed", "7", NULL};
    expect_usage_error(a3, "no output");
    char *a4[] = {"uwbsim", "--scene", bad, "-o", scan, NULL};
    expect_usage_error(a4, "colour");
    char *a5[] = {"uwbsim", "--seed", "-1", "-o", scan, NULL};
    expect_usage_error(a5, "seed");
    char *a6[] = {"uwbsim", "--height-change-m", "-0.05", "-o", scan, NULL};
    expect_usage_error(a6, "height_change_m");
    char *a7[] = {"uwbsim", "--radial-m", "2-9:0.006", "-o", scan, NULL};
    expect_usage_error(a7, "radial_m: disks 2-9: the winding has fewer disks");
    char *a8[] = {"uwbsim", "--radial-m=2-4:6mm", "-o", scan, NULL};
    expect_usage_error(a8, "\"2-4:6mm\" is not FROM-TO:METRES");
    char *a9[] = {"uwbsim", "--face-tilt-m", "-0.07", "-o", scan, NULL};
    expect_usage_error(a9, "through its back face");
    TEST_ASSERT_EQUAL_INT(-1, access(scan, F_OK)); /* nothing written on error */
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_help_lists_every_parameter_with_unit_and_default);
    RUN_TEST(test_markdown_table_has_a_row_per_parameter);
    RUN_TEST(test_writes_scan_and_truth);
    RUN_TEST(test_usage_errors);
    return UNITY_END();
}
