/* The client side of the control socket (issue 27, break 3): connecting
 * waits at most its timeout for a daemon whose backlog is full, and a
 * daemon that turned the connection away before the command was sent is
 * heard: its refusal is read, not just "Broken pipe". */
#include "scratch_support.h"
#include "unity.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "control/control_socket.h"
#include "uwb/monotonic.h"

static char dir[256], path[300], err[512];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "control-client");
    snprintf(path, sizeof path, "%s/control.sock", dir);
}

void tearDown(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, scratch_remove_tree(dir), dir);
}

static int listen_at(const char *where, int backlog)
{
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    TEST_ASSERT_TRUE(strlen(where) < sizeof a.sun_path);
    memcpy(a.sun_path, where, strlen(where) + 1);
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    TEST_ASSERT_TRUE(fd >= 0);
    TEST_ASSERT_EQUAL_INT(0, bind(fd, (struct sockaddr *)&a, sizeof a));
    TEST_ASSERT_EQUAL_INT(0, listen(fd, backlog));
    return fd;
}

static void test_a_full_backlog_times_out_within_the_timeout(void)
{
    int listener = listen_at(path, 0);
    int queued = uwbd_control_connect(path, 1.0, err, sizeof err); /* backlog 0 takes one */
    TEST_ASSERT_TRUE_MESSAGE(queued >= 0, err);
    double t0 = uwb_monotonic_s();
    int fd = uwbd_control_connect(path, 0.3, err, sizeof err);
    double took = uwb_monotonic_s() - t0;
    TEST_ASSERT_EQUAL_INT(UWBD_CONTROL_CONNECT_TIMEOUT, fd);
    TEST_ASSERT_TRUE_MESSAGE(took >= 0.25 && took < 2.0,
                             "the wait is the timeout (slack for a loaded machine)");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "did not accept the connection within 0.3 s"), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, path), err);
    close(queued);
    close(listener);
}

static void test_no_listener_fails_at_once(void)
{
    int fd = uwbd_control_connect(path, 5.0, err, sizeof err);
    TEST_ASSERT_EQUAL_INT(UWBD_CONTROL_CONNECT_FAILED, fd);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "cannot connect"), err);
}

static void test_the_refusal_is_read_after_a_broken_pipe(void)
{
    int pair[2];
    TEST_ASSERT_EQUAL_INT(0, socketpair(AF_UNIX, SOCK_STREAM, 0, pair));
    /* The daemon: a refusal line, then close, before the client sends. */
    static const char refusal[] = "{\"class\":\"ERROR\",\"message\":\"too many control clients\"}\n";
    TEST_ASSERT_EQUAL_INT((int)strlen(refusal), (int)send(pair[1], refusal, strlen(refusal), 0));
    close(pair[1]);
    char reason[256];
    errno = 0;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_control_send(pair[0], "status\n", 7, reason, sizeof reason));
    TEST_ASSERT_TRUE(errno == EPIPE || errno == ECONNRESET);
    TEST_ASSERT_EQUAL_STRING("{\"class\":\"ERROR\",\"message\":\"too many control clients\"}", reason);
    close(pair[0]);
}

static void test_a_silent_close_leaves_no_reason(void)
{
    int pair[2];
    TEST_ASSERT_EQUAL_INT(0, socketpair(AF_UNIX, SOCK_STREAM, 0, pair));
    close(pair[1]);
    char reason[256] = "stale";
    TEST_ASSERT_EQUAL_INT(-1, uwbd_control_send(pair[0], "status\n", 7, reason, sizeof reason));
    TEST_ASSERT_EQUAL_INT(EPIPE, errno);
    TEST_ASSERT_EQUAL_STRING("", reason);
    close(pair[0]);
}

static void test_a_send_that_goes_through_is_zero(void)
{
    int pair[2];
    TEST_ASSERT_EQUAL_INT(0, socketpair(AF_UNIX, SOCK_STREAM, 0, pair));
    char reason[256];
    TEST_ASSERT_EQUAL_INT(0, uwbd_control_send(pair[0], "status\n", 7, reason, sizeof reason));
    char got[16] = {0};
    TEST_ASSERT_EQUAL_INT(7, (int)recv(pair[1], got, sizeof got - 1, 0));
    TEST_ASSERT_EQUAL_STRING("status\n", got);
    close(pair[0]);
    close(pair[1]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_full_backlog_times_out_within_the_timeout);
    RUN_TEST(test_no_listener_fails_at_once);
    RUN_TEST(test_the_refusal_is_read_after_a_broken_pipe);
    RUN_TEST(test_a_silent_close_leaves_no_reason);
    RUN_TEST(test_a_send_that_goes_through_is_zero);
    return UNITY_END();
}
