/* The fuzz corpora as regression tests: every file of
 * tests/fuzz/corpus/<name>/ and tests/fuzz/regressions/<name>/ goes
 * through the harness of tests/fuzz/fuzz_<name>.c, the same code
 * `make fuzz` runs under libFuzzer, here in the normal (or SAN=1) build.
 * No file may break the parser's contract; a refusal must carry a
 * message; and each corpus must hold at least one input its parser
 * accepts, so that a format change that turns the seeds into garbage is
 * noticed here rather than by a fuzzer that quietly stops going deep. */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../fuzz/fuzz_harness.h"
#include "unity.h"
#include "uwb/read_file.h"

/* Far above any corpus input; bounds what a stray large file costs. */
#define CORPUS_FILE_MAX_BYTES ((size_t)16 * 1024 * 1024)

struct target {
    const char *name;
    fuzz_harness_fn harness;
};

static const struct target targets[] = {
    {"scan", fuzz_scan_input},
    {"frame", fuzz_frame_input},
    {"digitiser", fuzz_digitiser_input},
    {"config", fuzz_config_input},
    {"command", fuzz_command_input},
    {"gpio_reply", fuzz_gpio_reply_input},
    {"gpio_board", fuzz_gpio_board_input},
    {"analysis", fuzz_analysis_input},
    {"state", fuzz_state_input},
    {"set", fuzz_set_input},
    {"ctl_reply", fuzz_ctl_reply_input},
};

struct tally {
    int files, accepted;
};

void setUp(void)
{
}
void tearDown(void)
{
}

/* An exact-size copy of the file (the reader leaves a NUL after the bytes),
 * so ASan sees a harness reading one byte past the end. NULL with err
 * filled when unreadable. */
static uint8_t *read_exact(const char *path, size_t *size, char *err, size_t errlen)
{
    char *text;
    if (uwb_read_file(path, CORPUS_FILE_MAX_BYTES, &text, size, err, errlen) != UWB_READ_OK)
        return NULL;
    uint8_t *exact = malloc(*size ? *size : 1);
    if (exact)
        memcpy(exact, text, *size);
    else
        snprintf(err, errlen, "%s: out of memory", path);
    free(text);
    return exact;
}

/* Runs every file of dir through the harness; a missing dir is fine when
 * it is not required. */
static void run_dir(const struct target *t, const char *dir, int required, struct tally *tally)
{
    DIR *d = opendir(dir);
    if (!d) {
        char message[512];
        snprintf(message, sizeof message, "%s: %s", dir, strerror(errno));
        if (required)
            TEST_FAIL_MESSAGE(message);
        return;
    }
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (e->d_name[0] == '.')
            continue;
        char path[1024], message[1600], why[1024] = "";
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        size_t size = 0;
        uint8_t *data = read_exact(path, &size, message, sizeof message);
        TEST_ASSERT_NOT_NULL_MESSAGE(data, message);
        int rc = t->harness(data, size, why, sizeof why);
        free(data);
        snprintf(message, sizeof message, "%s: %s", path, why);
        TEST_ASSERT_TRUE_MESSAGE(rc != FUZZ_BROKEN, message);
        TEST_ASSERT_TRUE_MESSAGE(rc != FUZZ_REJECTED || why[0] != '\0', message);
        tally->files++;
        tally->accepted += rc == FUZZ_ACCEPTED;
    }
    closedir(d);
}

static void run_target(const char *name)
{
    const struct target *t = NULL;
    for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++)
        if (strcmp(targets[i].name, name) == 0)
            t = &targets[i];
    TEST_ASSERT_NOT_NULL_MESSAGE(t, name);
    char dir[256], message[300];
    struct tally corpus = {0, 0}, regressions = {0, 0};
    snprintf(dir, sizeof dir, "tests/fuzz/corpus/%s", name);
    run_dir(t, dir, 1, &corpus);
    snprintf(message, sizeof message, "%s: no seed", dir);
    TEST_ASSERT_TRUE_MESSAGE(corpus.files > 0, message);
    snprintf(message, sizeof message, "%s: none of %d seeds is accepted by its parser", dir, corpus.files);
    TEST_ASSERT_TRUE_MESSAGE(corpus.accepted > 0, message);
    snprintf(dir, sizeof dir, "tests/fuzz/regressions/%s", name);
    run_dir(t, dir, 0, &regressions);
}

static void test_scan_corpus(void)
{
    run_target("scan");
}
static void test_frame_corpus(void)
{
    run_target("frame");
}
static void test_digitiser_corpus(void)
{
    run_target("digitiser");
}
static void test_config_corpus(void)
{
    run_target("config");
}
static void test_command_corpus(void)
{
    run_target("command");
}
static void test_gpio_reply_corpus(void)
{
    run_target("gpio_reply");
}
static void test_gpio_board_corpus(void)
{
    run_target("gpio_board");
}
static void test_analysis_corpus(void)
{
    run_target("analysis");
}
static void test_state_corpus(void)
{
    run_target("state");
}
static void test_set_corpus(void)
{
    run_target("set");
}
static void test_ctl_reply_corpus(void)
{
    run_target("ctl_reply");
}

/* Every tests/fuzz/fuzz_<name>.c has its entry above. */
static void test_every_fuzz_target_is_listed(void)
{
    DIR *d = opendir("tests/fuzz");
    TEST_ASSERT_NOT_NULL_MESSAGE(d, "tests/fuzz");
    int fuzz_files = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        size_t n = strlen(e->d_name);
        if (strncmp(e->d_name, "fuzz_", 5) != 0 || n < 8 || strcmp(e->d_name + n - 2, ".c") != 0)
            continue;
        char name[256];
        snprintf(name, sizeof name, "%.*s", (int)(n - 7), e->d_name + 5);
        int listed = 0;
        for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++)
            listed |= strcmp(targets[i].name, name) == 0;
        TEST_ASSERT_TRUE_MESSAGE(listed, e->d_name);
        fuzz_files++;
    }
    closedir(d);
    TEST_ASSERT_EQUAL_INT((int)(sizeof targets / sizeof targets[0]), fuzz_files);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_fuzz_target_is_listed);
    RUN_TEST(test_scan_corpus);
    RUN_TEST(test_frame_corpus);
    RUN_TEST(test_digitiser_corpus);
    RUN_TEST(test_config_corpus);
    RUN_TEST(test_command_corpus);
    RUN_TEST(test_gpio_reply_corpus);
    RUN_TEST(test_gpio_board_corpus);
    RUN_TEST(test_analysis_corpus);
    RUN_TEST(test_state_corpus);
    RUN_TEST(test_set_corpus);
    RUN_TEST(test_ctl_reply_corpus);
    return UNITY_END();
}
