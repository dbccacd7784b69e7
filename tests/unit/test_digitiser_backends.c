/* The digitiser's backend table (src/digitiser/digitiser.c): a model is
 * found by name, an unknown one is refused naming it, and uwb_digitiser_open
 * goes through the table's framed row. */
#include <string.h>

#include "digitiser/digitiser_backend.h"
#include "unity.h"
#include "uwb/digitiser.h"
#include "uwb/link.h"

static char err[512];

void setUp(void)
{
    err[0] = '\0';
}
void tearDown(void)
{
}

/* A configuration no backend should get as far as opening a link with. */
static struct uwb_digitiser_config config(int samples)
{
    struct uwb_digitiser_config cfg = {.samples = samples,
                                       .sample_interval_s = 1e-11,
                                       .stack = 1,
                                       .frame_timeout_ms = 100,
                                       .frame_retries = 0};
    strcpy(cfg.endpoint, "unix:/nonexistent/uwbd-test-digitiser.sock");
    return cfg;
}

static void test_the_framed_backend_is_found_by_name(void)
{
    TEST_ASSERT_EQUAL_PTR(&uwb_digitiser_framed_backend,
                          uwb_digitiser_backend_find("framed", err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("framed", UWB_DIGITISER_DEFAULT_MODEL);
}

static void test_an_unknown_model_is_refused_naming_it_and_the_known_ones(void)
{
    TEST_ASSERT_NULL(uwb_digitiser_backend_find("acme-9000", err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("digitiser model 'acme-9000' unknown (known: framed)", err);

    struct uwb_digitiser_config cfg = config(64);
    struct uwb_digitiser *dig = (struct uwb_digitiser *)&cfg; /* must be cleared */
    int detail = UWB_LINK_ERR_OPEN;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_CONFIG,
                          uwb_digitiser_open_model("acme-9000", &cfg, &dig, &detail, err, sizeof err));
    TEST_ASSERT_NULL(dig);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, detail);
    TEST_ASSERT_EQUAL_STRING("digitiser model 'acme-9000' unknown (known: framed)", err);
}

/* The default model's open is the framed backend's: its own check of the
 * record length against the frame limit answers, and its link open. */
static void test_open_goes_through_the_framed_row(void)
{
    struct uwb_digitiser_config cfg = config(0);
    struct uwb_digitiser *dig = NULL;
    int detail = UWB_LINK_OK;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_PROTOCOL,
                          uwb_digitiser_open(&cfg, &dig, &detail, err, sizeof err));
    TEST_ASSERT_NULL(dig);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "samples must be 1..65536"), err);

    cfg = config(64);
    char by_model[512];
    int detail_by_model = UWB_LINK_OK;
    TEST_ASSERT_EQUAL_INT(UWB_DIGITISER_ERR_LINK, uwb_digitiser_open(&cfg, &dig, &detail, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(
        UWB_DIGITISER_ERR_LINK,
        uwb_digitiser_open_model("framed", &cfg, &dig, &detail_by_model, by_model, sizeof by_model));
    TEST_ASSERT_NULL(dig);
    TEST_ASSERT_NOT_EQUAL(UWB_LINK_OK, detail);
    TEST_ASSERT_EQUAL_INT(detail, detail_by_model);
    TEST_ASSERT_EQUAL_STRING(err, by_model);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_the_framed_backend_is_found_by_name);
    RUN_TEST(test_an_unknown_model_is_refused_naming_it_and_the_known_ones);
    RUN_TEST(test_open_goes_through_the_framed_row);
    return UNITY_END();
}
