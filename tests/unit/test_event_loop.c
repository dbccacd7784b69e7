/* The daemon's event registry: what is registered is polled and its
 * callback run in registration order; a full table refuses; a callback may
 * remove its own entry or another's during dispatch. Pipes stand in for
 * the daemon's fds. */
#include <poll.h>
#include <unistd.h>

#include "unity.h"

#include "loop/event_loop.h"

static struct uwbd_event_loop loop;
static int pipes[3][2];
static int calls[8];
static int order[8], n_order;

void setUp(void)
{
    uwbd_event_loop_init(&loop);
    for (int i = 0; i < 3; i++) {
        TEST_ASSERT_EQUAL_INT(0, pipe(pipes[i]));
        TEST_ASSERT_EQUAL_INT(1, (int)write(pipes[i][1], "x", 1)); /* readable */
    }
    for (int i = 0; i < 8; i++)
        calls[i] = 0;
    n_order = 0;
}

void tearDown(void)
{
    for (int i = 0; i < 3; i++) {
        close(pipes[i][0]);
        close(pipes[i][1]);
    }
}

static void count(void *ctx, int fd, short revents)
{
    (void)fd;
    int which = *(int *)ctx;
    TEST_ASSERT_TRUE(revents & POLLIN);
    calls[which]++;
    order[n_order++] = which;
}

static int ids[3];
static const int which[3] = {0, 1, 2};

static void test_dispatches_what_fired_in_registration_order(void)
{
    for (int i = 2; i >= 0; i--) /* registered 2, 1, 0: slots 0, 1, 2 */
        ids[i] = uwbd_event_loop_add(&loop, pipes[i][0], POLLIN, count, (void *)&which[i]);
    char byte;
    TEST_ASSERT_EQUAL_INT(1, (int)read(pipes[1][0], &byte, 1)); /* pipe 1 no longer readable */
    TEST_ASSERT_EQUAL_INT(2, uwbd_event_loop_once(&loop, 0));
    TEST_ASSERT_EQUAL_INT(1, calls[0]);
    TEST_ASSERT_EQUAL_INT(0, calls[1]);
    TEST_ASSERT_EQUAL_INT(1, calls[2]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, order[0], "the first registered runs first");
    TEST_ASSERT_EQUAL_INT(0, order[1]);
}

static void test_removed_and_skipped_entries_are_not_polled(void)
{
    ids[0] = uwbd_event_loop_add(&loop, pipes[0][0], POLLIN, count, (void *)&which[0]);
    ids[1] = uwbd_event_loop_add(&loop, pipes[1][0], POLLIN, count, (void *)&which[1]);
    uwbd_event_loop_remove(&loop, ids[0]);
    uwbd_event_loop_set(&loop, ids[1], -1, POLLIN);
    TEST_ASSERT_EQUAL_INT(0, uwbd_event_loop_once(&loop, 0));
    TEST_ASSERT_EQUAL_INT(0, calls[0] + calls[1]);
    uwbd_event_loop_set(&loop, ids[1], pipes[1][0], POLLIN);
    TEST_ASSERT_EQUAL_INT(1, uwbd_event_loop_once(&loop, 0));
    TEST_ASSERT_EQUAL_INT(1, calls[1]);
}

static void test_a_full_table_refuses(void)
{
    for (int i = 0; i < UWBD_EVENT_LOOP_MAX; i++)
        TEST_ASSERT_EQUAL_INT(i, uwbd_event_loop_add(&loop, -1, POLLIN, count, (void *)&which[0]));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_event_loop_add(&loop, pipes[0][0], POLLIN, count, (void *)&which[0]));
    uwbd_event_loop_remove(&loop, 7);
    TEST_ASSERT_EQUAL_INT_MESSAGE(7, uwbd_event_loop_add(&loop, -1, POLLIN, count, (void *)&which[0]),
                                  "a freed slot is taken again");
    for (int i = 0; i < UWBD_EVENT_LOOP_HOOKS; i++)
        TEST_ASSERT_EQUAL_INT(i, uwbd_event_loop_add_hook(&loop, NULL, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_event_loop_add_hook(&loop, NULL, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_event_loop_add(&loop, 0, POLLIN, NULL, NULL));
}

/* Removes its own entry and the one registered after it. */
static void remove_self_and_next(void *ctx, int fd, short revents)
{
    count(ctx, fd, revents);
    uwbd_event_loop_remove(&loop, ids[0]);
    uwbd_event_loop_remove(&loop, ids[1]);
    /* the next one's slot taken again at once: not called with the old fd's events */
    ids[1] = uwbd_event_loop_add(&loop, pipes[1][0], POLLIN, count, (void *)&which[2]);
}

static void test_a_callback_may_remove_itself_or_another(void)
{
    ids[0] = uwbd_event_loop_add(&loop, pipes[0][0], POLLIN, remove_self_and_next, (void *)&which[0]);
    ids[1] = uwbd_event_loop_add(&loop, pipes[1][0], POLLIN, count, (void *)&which[1]);
    ids[2] = uwbd_event_loop_add(&loop, pipes[2][0], POLLIN, count, (void *)&which[2]);
    TEST_ASSERT_EQUAL_INT(2, uwbd_event_loop_once(&loop, 0));
    TEST_ASSERT_EQUAL_INT(1, calls[0]);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, calls[1], "removed before its turn");
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, calls[2], "the one after still runs");
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, uwbd_event_loop_once(&loop, 0), "the new entry and the third");
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, calls[0], "removed: not called again");
    TEST_ASSERT_EQUAL_INT(0, calls[1]);
    TEST_ASSERT_EQUAL_INT(3, calls[2]);
}

static int prepared, after_ran;
static int prepare_20ms(void *ctx)
{
    (void)ctx;
    prepared++;
    return 20;
}
static void after(void *ctx)
{
    (void)ctx;
    after_ran++;
}

static void test_hooks_bound_the_wait_and_run_after_every_round(void)
{
    prepared = after_ran = 0;
    int hook = uwbd_event_loop_add_hook(&loop, prepare_20ms, after, NULL);
    TEST_ASSERT_EQUAL_INT(0, hook);
    /* Nothing registered, no bound of its own: the hook's 20 ms ends the wait. */
    TEST_ASSERT_EQUAL_INT(0, uwbd_event_loop_once(&loop, -1));
    TEST_ASSERT_EQUAL_INT(1, prepared);
    TEST_ASSERT_EQUAL_INT(1, after_ran);
    uwbd_event_loop_remove_hook(&loop, hook);
    TEST_ASSERT_EQUAL_INT(0, uwbd_event_loop_once(&loop, 0));
    TEST_ASSERT_EQUAL_INT(1, after_ran);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_dispatches_what_fired_in_registration_order);
    RUN_TEST(test_removed_and_skipped_entries_are_not_polled);
    RUN_TEST(test_a_full_table_refuses);
    RUN_TEST(test_a_callback_may_remove_itself_or_another);
    RUN_TEST(test_hooks_bound_the_wait_and_run_after_every_round);
    return UNITY_END();
}
