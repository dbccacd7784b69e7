/* Socket links: a socketpair, a listening unix socket, a listening tcp
 * socket; timeouts, a vanished peer, bad endpoints. */
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scratch_support.h"
#include "unity.h"
#include "uwb/link.h"

static char dir[64];
static char err[512];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "link");
}

void tearDown(void)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, scratch_remove_tree(dir), dir);
}

static void pair(struct uwb_link **a, struct uwb_link **b)
{
    int fds[2];
    TEST_ASSERT_EQUAL_INT(0, socketpair(AF_UNIX, SOCK_STREAM, 0, fds));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_from_fd(fds[0], "pair-a", a, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_from_fd(fds[1], "pair-b", b, err, sizeof err));
}

/* `message` written on one end arrives whole at the other. */
static void assert_crosses(struct uwb_link *from, struct uwb_link *to, const char *message)
{
    size_t len = strlen(message);
    char buf[16];
    TEST_ASSERT_TRUE(len <= sizeof buf);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_write_all(from, message, len, 1000, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_read_exact(to, buf, len, 1000, err, sizeof err));
    TEST_ASSERT_EQUAL_MEMORY(message, buf, len);
}

static void test_bytes_cross_and_read_exact_gathers_chunks(void)
{
    struct uwb_link *a, *b;
    pair(&a, &b);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_write_all(a, "hello ", 6, 1000, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_write_all(a, "world", 5, 1000, err, sizeof err));
    char buf[16] = "";
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_read_exact(b, buf, 11, 1000, err, sizeof err));
    TEST_ASSERT_EQUAL_MEMORY("hello world", buf, 11);
    TEST_ASSERT_TRUE(uwb_link_fd(b) >= 0);
    uwb_link_close(a);
    uwb_link_close(b);
}

static void test_read_times_out_then_sees_a_closed_peer(void)
{
    struct uwb_link *a, *b;
    pair(&a, &b);
    char buf[4];
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_TIMEOUT, (int)uwb_link_read(b, buf, sizeof buf, 20, err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "pair-b"));
    /* half a message, then the peer goes: read_exact reports what it got */
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_write_all(a, "ab", 2, 1000, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_TIMEOUT, uwb_link_read_exact(b, buf, 4, 30, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "2 of 4 bytes"), err);
    uwb_link_close(a);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_IO, (int)uwb_link_read(b, buf, sizeof buf, 1000, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "closed"), err);
    /* writing to a vanished peer is an error, not a SIGPIPE */
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_IO, uwb_link_write_all(b, "x", 1, 1000, err, sizeof err));
    uwb_link_close(b);
}

static void test_unix_listener_accepts_one_peer_after_another(void)
{
    char endpoint[128], path[100];
    snprintf(path, sizeof path, "%s/s.sock", dir);
    snprintf(endpoint, sizeof endpoint, "unix:%s", path);
    struct uwb_link_listener *l;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_listen(endpoint, &l, err, sizeof err), err);
    for (int round = 0; round < 2; round++) {
        struct uwb_link *client, *server;
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_open(endpoint, &client, err, sizeof err), err);
        TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_accept(l, &server, 1000, err, sizeof err));
        TEST_ASSERT_EQUAL_STRING(endpoint, uwb_link_name(client));
        assert_crosses(client, server, "ping");
        uwb_link_close(client);
        uwb_link_close(server);
    }
    struct uwb_link *none;
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_TIMEOUT, uwb_link_accept(l, &none, 10, err, sizeof err));
    uwb_link_listener_close(l);
    struct stat st;
    TEST_ASSERT_NOT_EQUAL(0, stat(path, &st)); /* the socket file is gone */
}

static void test_listener_replaces_a_stale_socket_but_not_a_file(void)
{
    char endpoint[128], path[100];
    snprintf(path, sizeof path, "%s/s.sock", dir);
    snprintf(endpoint, sizeof endpoint, "unix:%s", path);
    struct uwb_link_listener *l1, *l2;
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_listen(endpoint, &l1, err, sizeof err));
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_listen(endpoint, &l2, err, sizeof err), err);
    uwb_link_listener_close(l2);
    uwb_link_listener_close(l1);

    snprintf(path, sizeof path, "%s/plain", dir);
    snprintf(endpoint, sizeof endpoint, "unix:%s", path);
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN, uwb_link_listen(endpoint, &l1, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "not a socket"), err);
}

static void test_tcp_listener_and_client(void)
{
    struct uwb_link_listener *l = NULL;
    char endpoint[64];
    /* a free port: try a few from a pid-dependent start */
    for (int i = 0; i < 50 && !l; i++) {
        snprintf(endpoint, sizeof endpoint, "tcp:127.0.0.1:%d", 20000 + (getpid() * 7 + i * 131) % 40000);
        if (uwb_link_listen(endpoint, &l, err, sizeof err) != UWB_LINK_OK)
            l = NULL;
    }
    TEST_ASSERT_NOT_NULL_MESSAGE(l, err);
    struct uwb_link *client, *server;
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_LINK_OK, uwb_link_open(endpoint, &client, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_OK, uwb_link_accept(l, &server, 1000, err, sizeof err));
    assert_crosses(server, client, "frame");
    uwb_link_close(client);
    uwb_link_close(server);
    uwb_link_listener_close(l);
    /* nobody listens there now */
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN, uwb_link_open(endpoint, &client, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, endpoint), err);
}

static void test_missing_socket_and_bad_endpoint(void)
{
    struct uwb_link *link = (struct uwb_link *)1;
    char endpoint[128];
    snprintf(endpoint, sizeof endpoint, "unix:%s/nobody.sock", dir);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_OPEN, uwb_link_open(endpoint, &link, err, sizeof err));
    TEST_ASSERT_NULL(link);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "nobody.sock"), err);
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_ENDPOINT, uwb_link_open("ftp:x", &link, err, sizeof err));
    struct uwb_link_listener *l;
    TEST_ASSERT_EQUAL_INT(UWB_LINK_ERR_ENDPOINT, uwb_link_listen("serial:/dev/ttyS0", &l, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "only unix: and tcp:"), err);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_bytes_cross_and_read_exact_gathers_chunks);
    RUN_TEST(test_read_times_out_then_sees_a_closed_peer);
    RUN_TEST(test_unix_listener_accepts_one_peer_after_another);
    RUN_TEST(test_listener_replaces_a_stale_socket_but_not_a_file);
    RUN_TEST(test_tcp_listener_and_client);
    RUN_TEST(test_missing_socket_and_bad_endpoint);
    return UNITY_END();
}
