/* uwb_read_file / uwb_read_fd: bytes exact with a NUL after them, the size
 * limit enforced for files and for streams whose size is not known, and
 * every refusal naming the input. */
#include "scratch_support.h"
#include "unity.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "uwb/read_file.h"

static char tmpdir[64];
static char path[128];
static char err[512];
static char *buf;
static size_t len;

void setUp(void)
{
    scratch_scratch_dir(tmpdir, sizeof tmpdir, "read-file");
    snprintf(path, sizeof path, "%s/input", tmpdir);
    err[0] = '\0';
    buf = NULL;
    len = 0;
}

void tearDown(void)
{
    free(buf);
    scratch_remove_tree(tmpdir);
}

static void write_bytes(const char *p, const void *data, size_t n)
{
    FILE *f = fopen(p, "wb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, p);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)n, (uint64_t)fwrite(data, 1, n, f));
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
}

static void assert_err_contains(const char *part)
{
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, part), err);
}

static void test_reads_bytes_exactly_with_a_nul_after_them(void)
{
    /* NULs and high bytes inside, so nothing stops at the first NUL. */
    const unsigned char data[] = {'a', 0, 0xff, '\n', 0x80, 'z'};
    write_bytes(path, data, sizeof data);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_READ_OK, uwb_read_file(path, 1024, &buf, &len, err, sizeof err), err);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)sizeof data, (uint64_t)len);
    TEST_ASSERT_EQUAL_MEMORY(data, buf, sizeof data);
    TEST_ASSERT_EQUAL_INT(0, buf[len]);
}

static void test_empty_file_gives_an_empty_string(void)
{
    write_bytes(path, "", 0);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_READ_OK, uwb_read_file(path, 16, &buf, &len, err, sizeof err), err);
    TEST_ASSERT_EQUAL_UINT64(0, (uint64_t)len);
    TEST_ASSERT_NOT_NULL(buf);
    TEST_ASSERT_EQUAL_INT(0, buf[0]);
}

static void test_file_of_exactly_the_limit_is_read(void)
{
    char data[64];
    memset(data, 'x', sizeof data);
    write_bytes(path, data, sizeof data);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_READ_OK, uwb_read_file(path, sizeof data, &buf, &len, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)sizeof data, (uint64_t)len);
}

/* Reading path with max_bytes is refused as want, with nothing handed
 * back and the message "PATH: problem". */
static void assert_refused(size_t max_bytes, enum uwb_read_result want, const char *problem)
{
    TEST_ASSERT_EQUAL_INT(want, uwb_read_file(path, max_bytes, &buf, &len, err, sizeof err));
    TEST_ASSERT_NULL(buf);
    TEST_ASSERT_EQUAL_UINT64(0, (uint64_t)len);
    char expected[256];
    snprintf(expected, sizeof expected, "%s: %s", path, problem);
    TEST_ASSERT_EQUAL_STRING(expected, err);
}

static void test_file_over_the_limit_is_refused_with_path_and_sizes(void)
{
    char data[100];
    memset(data, 'x', sizeof data);
    write_bytes(path, data, sizeof data);
    assert_refused(64, UWB_READ_TOO_BIG, "too big: 100 bytes, over the limit of 64");
}

static void test_missing_file_is_named(void)
{
    snprintf(path, sizeof path, "%s/absent", tmpdir);
    assert_refused(64, UWB_READ_FAILED, "cannot open: No such file or directory");
}

static void test_directory_is_refused(void)
{
    TEST_ASSERT_EQUAL_INT(UWB_READ_FAILED, uwb_read_file(tmpdir, 64, &buf, &len, err, sizeof err));
    TEST_ASSERT_NULL(buf);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err, tmpdir, strlen(tmpdir)) == 0, err);
    assert_err_contains("cannot open: Is a directory");
}

/* Byte i of the streams below: its period (251, a prime) divides no power
 * of two, so a chunk the reader put at a wrong offset shows. */
static char pattern_byte(size_t i)
{
    return (char)(i % 251);
}

/* A pipe fed n pattern bytes by a child, so the reader must grow its
 * buffer without knowing the size; returns the read end. */
static int pipe_from_child(size_t n, pid_t *child)
{
    int fds[2];
    TEST_ASSERT_EQUAL_INT(0, pipe(fds));
    *child = fork();
    TEST_ASSERT_TRUE(*child >= 0);
    if (*child == 0) {
        close(fds[0]);
        char block[4096];
        for (size_t sent = 0; sent < n;) {
            size_t chunk = n - sent < sizeof block ? n - sent : sizeof block;
            for (size_t k = 0; k < chunk; k++)
                block[k] = pattern_byte(sent + k);
            ssize_t w = write(fds[1], block, chunk);
            /* The reader may stop early (over its limit); that is allowed. */
            if (w <= 0)
                _exit(0);
            sent += (size_t)w;
        }
        _exit(0);
    }
    close(fds[1]);
    return fds[0];
}

static void finish_child(int fd, pid_t child)
{
    close(fd);
    int status;
    TEST_ASSERT_EQUAL_INT(child, waitpid(child, &status, 0));
}

static void test_stream_larger_than_the_first_buffer_is_read_whole(void)
{
    /* Several times the reader's first buffer for an unknown size. */
    const size_t n = 300000;
    pid_t child;
    int fd = pipe_from_child(n, &child);
    int rc = uwb_read_fd(fd, "pipe", n, &buf, &len, err, sizeof err);
    finish_child(fd, child);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_READ_OK, rc, err);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)n, (uint64_t)len);
    for (size_t i = 0; i < n; i++)
        if (buf[i] != pattern_byte(i))
            TEST_FAIL_MESSAGE("byte out of place");
    TEST_ASSERT_EQUAL_INT(0, buf[len]);
}

static void test_stream_over_the_limit_is_refused_with_name_and_limit(void)
{
    pid_t child;
    int fd = pipe_from_child(200000, &child);
    int rc = uwb_read_fd(fd, "pipe", 100000, &buf, &len, err, sizeof err);
    finish_child(fd, child);
    TEST_ASSERT_EQUAL_INT(UWB_READ_TOO_BIG, rc);
    TEST_ASSERT_NULL(buf);
    TEST_ASSERT_EQUAL_STRING("pipe: too big: over the limit of 100000 bytes", err);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_reads_bytes_exactly_with_a_nul_after_them);
    RUN_TEST(test_empty_file_gives_an_empty_string);
    RUN_TEST(test_file_of_exactly_the_limit_is_read);
    RUN_TEST(test_file_over_the_limit_is_refused_with_path_and_sizes);
    RUN_TEST(test_missing_file_is_named);
    RUN_TEST(test_directory_is_refused);
    RUN_TEST(test_stream_larger_than_the_first_buffer_is_read_whole);
    RUN_TEST(test_stream_over_the_limit_is_refused_with_name_and_limit);
    return UNITY_END();
}
