/* atomic_file: the target is replaced whole or not at all, the temporary
 * lives beside it, and nothing is left behind on success or failure.
 * Failure modes are ones root cannot bypass (tests may run as root). */
#include "scratch_support.h"
#include "unity.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "uwb/atomic_file.h"

static char tmpdir[64];
static char err[512];

static int compare_names(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

/* Names in dir, sorted and joined with ' ', so a stray temp shows up in a diff. */
static const char *listing(const char *dir)
{
    static char out[1024];
    char names[32][256];
    int n = 0;
    DIR *d = opendir(dir);
    TEST_ASSERT_NOT_NULL(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL && n < 32)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            snprintf(names[n++], sizeof names[0], "%s", e->d_name);
    closedir(d);
    qsort(names, (size_t)n, sizeof names[0], compare_names);
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        if (i)
            strcat(out, " ");
        strcat(out, names[i]);
    }
    return out;
}

static void write_plain(const char *path, const char *text)
{
    FILE *fp = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(fp);
    fputs(text, fp);
    TEST_ASSERT_EQUAL_INT(0, fclose(fp));
}

static const char *read_plain(const char *path)
{
    static char buf[4096];
    FILE *fp = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(fp, path);
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    buf[n] = '\0';
    fclose(fp);
    return buf;
}

static void in_tmp(char *out, size_t outlen, const char *name)
{
    snprintf(out, outlen, "%s/%s", tmpdir, name);
}

void setUp(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/test_atomic.XXXXXX");
    TEST_ASSERT_NOT_NULL(mkdtemp(tmpdir));
    err[0] = '\0';
}

void tearDown(void)
{
    scratch_remove_tree(tmpdir);
}

static void test_creates_new_file(void)
{
    char path[256];
    in_tmp(path, sizeof path, "new.json");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_write_file(path, "{\"a\":1}\n", 8, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("{\"a\":1}\n", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("new.json", listing(tmpdir));
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(path, &st));
    TEST_ASSERT_EQUAL_INT(0644, st.st_mode & 07777); /* not mkstemp's private 0600 */
}

static void test_replaces_existing_file_and_keeps_its_mode(void)
{
    char path[256];
    in_tmp(path, sizeof path, "verdict.json");
    write_plain(path, "old content that is longer than the new one");
    TEST_ASSERT_EQUAL_INT(0, chmod(path, 0640));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_write_file(path, "new", 3, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("new", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("verdict.json", listing(tmpdir));
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(path, &st));
    TEST_ASSERT_EQUAL_INT(0640, st.st_mode & 07777);
}

static void test_empty_content_gives_empty_file(void)
{
    char path[256];
    in_tmp(path, sizeof path, "empty");
    write_plain(path, "something");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_write_file(path, NULL, 0, err, sizeof err), err);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(path, &st));
    TEST_ASSERT_EQUAL_INT64(0, st.st_size);
}

static void test_temporary_is_a_hidden_sibling_until_commit(void)
{
    char path[256];
    in_tmp(path, sizeof path, "scan.uwbscan");
    write_plain(path, "old");
    struct atomic_file af;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_file_open(&af, path, err, sizeof err), err);
    char prefix[256];
    snprintf(prefix, sizeof prefix, "%s/" ATOMIC_FILE_TEMP_PREFIX "scan.uwbscan.", tmpdir);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(af.temp_path, prefix, strlen(prefix)) == 0, af.temp_path);
    const char *temp_name = strrchr(af.temp_path, '/') + 1;
    /* A name only uwbd makes: the start-up cleanup removes nothing else. */
    TEST_ASSERT_TRUE_MESSAGE(uwb_atomic_file_is_temporary_name(temp_name), temp_name);
    TEST_ASSERT_FALSE(uwb_atomic_file_is_temporary_name(".scan.uwbscan.Ab12Cd"));
    TEST_ASSERT_FALSE(uwb_atomic_file_is_temporary_name(".bashrc.backup"));
    TEST_ASSERT_FALSE(uwb_atomic_file_is_temporary_name(ATOMIC_FILE_TEMP_PREFIX "x.Ab12C.part"));
    TEST_ASSERT_EQUAL_STRING(path, af.final_path);
    fputs("new", af.fp);
    /* Before the commit, readers still see the old content. */
    TEST_ASSERT_EQUAL_STRING("old", read_plain(path));
    TEST_ASSERT_EQUAL_INT(0, access(af.temp_path, F_OK));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_file_commit(&af, err, sizeof err), err);
    TEST_ASSERT_EQUAL_STRING("new", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("scan.uwbscan", listing(tmpdir));
    uwb_atomic_file_abort(&af); /* after a commit: does nothing, removes nothing */
    TEST_ASSERT_EQUAL_STRING("new", read_plain(path));
}

static void test_abort_discards_and_leaves_target(void)
{
    char path[256];
    in_tmp(path, sizeof path, "kept.txt");
    write_plain(path, "precious");
    struct atomic_file af;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_file_open(&af, path, err, sizeof err), err);
    fputs("half-written", af.fp);
    uwb_atomic_file_abort(&af);
    TEST_ASSERT_EQUAL_STRING("precious", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("kept.txt", listing(tmpdir));
    uwb_atomic_file_abort(&af); /* twice is harmless */
}

static void test_failed_commit_keeps_old_target_and_removes_temp(void)
{
    /* The target is a non-empty directory: rename cannot replace it, not even as root. */
    char path[256], inner[300];
    in_tmp(path, sizeof path, "target");
    TEST_ASSERT_EQUAL_INT(0, mkdir(path, 0755));
    snprintf(inner, sizeof inner, "%s/inside.txt", path);
    write_plain(inner, "old content");

    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_write_file(path, "new", 3, err, sizeof err));
    char expected[512];
    snprintf(expected, sizeof expected, "%s: cannot replace with new file: %s", path, strerror(EISDIR));
    TEST_ASSERT_EQUAL_STRING(expected, err);
    TEST_ASSERT_EQUAL_STRING("old content", read_plain(inner));
    TEST_ASSERT_EQUAL_STRING("target", listing(tmpdir));
}

static void test_commit_failure_after_writing_keeps_old_file(void)
{
    /* The temporary vanishes before the commit (e.g. a cleaner removed it):
     * the rename fails and the old regular file must be untouched. */
    char path[256];
    in_tmp(path, sizeof path, "data.bin");
    write_plain(path, "generation 1");
    struct atomic_file af;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_atomic_file_open(&af, path, err, sizeof err), err);
    fputs("generation 2", af.fp);
    TEST_ASSERT_EQUAL_INT(0, unlink(af.temp_path));
    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_file_commit(&af, err, sizeof err));
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err, path, strlen(path)) == 0, err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, strerror(ENOENT)), err);
    TEST_ASSERT_EQUAL_STRING("generation 1", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("data.bin", listing(tmpdir));
    TEST_ASSERT_NULL(af.fp);
}

static void test_missing_parent_directory_is_reported(void)
{
    char path[256];
    in_tmp(path, sizeof path, "no/such/dir/out.json");
    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_write_file(path, "x", 1, err, sizeof err));
    char expected[512];
    snprintf(expected, sizeof expected, "%s: cannot create temporary file: %s", path, strerror(ENOENT));
    TEST_ASSERT_EQUAL_STRING(expected, err);
    TEST_ASSERT_EQUAL_STRING("", listing(tmpdir));
}

static void test_rejects_paths_that_name_no_file(void)
{
    struct atomic_file af;
    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_file_open(&af, "", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "empty path"));
    char path[256];
    snprintf(path, sizeof path, "%s/", tmpdir);
    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_file_open(&af, path, err, sizeof err));
    char expected[512];
    snprintf(expected, sizeof expected, "%s: path names a directory, not a file", path);
    TEST_ASSERT_EQUAL_STRING(expected, err);
    uwb_atomic_file_abort(&af); /* safe on a failed open */

    char longpath[5000];
    memset(longpath, 'a', sizeof longpath - 1);
    longpath[sizeof longpath - 1] = '\0';
    TEST_ASSERT_EQUAL_INT(-1, uwb_atomic_file_open(&af, longpath, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "path is too long"), err);
    TEST_ASSERT_EQUAL_STRING("", listing(tmpdir));
}

static void test_bare_file_name_uses_current_directory(void)
{
    char cwd[4096];
    TEST_ASSERT_NOT_NULL(getcwd(cwd, sizeof cwd));
    TEST_ASSERT_EQUAL_INT(0, chdir(tmpdir));
    struct atomic_file af;
    int rc = uwb_atomic_file_open(&af, "plain.txt", err, sizeof err);
    int temp_is_local = rc == 0 && strncmp(af.temp_path, ATOMIC_FILE_TEMP_PREFIX "plain.txt.",
                                           strlen(ATOMIC_FILE_TEMP_PREFIX "plain.txt.")) == 0;
    if (rc == 0) {
        fputs("here", af.fp);
        rc = uwb_atomic_file_commit(&af, err, sizeof err);
    }
    TEST_ASSERT_EQUAL_INT(0, chdir(cwd));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
    TEST_ASSERT_TRUE(temp_is_local);
    char path[256];
    in_tmp(path, sizeof path, "plain.txt");
    TEST_ASSERT_EQUAL_STRING("here", read_plain(path));
    TEST_ASSERT_EQUAL_STRING("plain.txt", listing(tmpdir));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_creates_new_file);
    RUN_TEST(test_replaces_existing_file_and_keeps_its_mode);
    RUN_TEST(test_empty_content_gives_empty_file);
    RUN_TEST(test_temporary_is_a_hidden_sibling_until_commit);
    RUN_TEST(test_abort_discards_and_leaves_target);
    RUN_TEST(test_failed_commit_keeps_old_target_and_removes_temp);
    RUN_TEST(test_commit_failure_after_writing_keeps_old_file);
    RUN_TEST(test_missing_parent_directory_is_reported);
    RUN_TEST(test_rejects_paths_that_name_no_file);
    RUN_TEST(test_bare_file_name_uses_current_directory);
    return UNITY_END();
}
