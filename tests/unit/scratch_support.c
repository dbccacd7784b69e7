/* Scratch directories and small files for tests (see scratch_support.h). */
#include "scratch_support.h"

#include "unity.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "uwb/read_file.h"

/* Far above any file a test writes or reads back. */
#define SCRATCH_SLURP_MAX_BYTES ((size_t)64 * 1024 * 1024)

void scratch_scratch_dir(char *path, size_t n, const char *tag)
{
    snprintf(path, n, "/tmp/uwbd-%s-XXXXXX", tag);
    TEST_ASSERT_NOT_NULL_MESSAGE(mkdtemp(path), "mkdtemp");
}

int scratch_remove_tree(const char *path)
{
    DIR *d = opendir(path);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            char child[2048];
            snprintf(child, sizeof child, "%s/%s", path, e->d_name);
            struct stat st;
            if (lstat(child, &st) == 0 && S_ISDIR(st.st_mode))
                scratch_remove_tree(child);
            else
                unlink(child);
        }
        closedir(d);
    }
    return rmdir(path) == 0 || errno == ENOENT ? 0 : -1;
}

char *scratch_slurp(const char *path, size_t *len)
{
    char *text, err[512];
    size_t n;
    uwb_read_file(path, SCRATCH_SLURP_MAX_BYTES, &text, &n, err, sizeof err);
    if (len)
        *len = n;
    return text;
}

void scratch_assert_file_holds(const char *path, const char *expected, size_t len)
{
    size_t got_len = 0;
    char *got = scratch_slurp(path, &got_len);
    TEST_ASSERT_NOT_NULL_MESSAGE(got, path);
    TEST_ASSERT_EQUAL_UINT64_MESSAGE(len, got_len, path);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(expected, got, len, path);
    free(got);
}

void scratch_spit(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    fputs(text, f);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
}

int scratch_file_exists(const char *path)
{
    return access(path, F_OK) == 0;
}

int scratch_count_lines(const char *path)
{
    size_t len = 0;
    char *text = scratch_slurp(path, &len);
    if (!text)
        return 0;
    int n = 0;
    for (size_t i = 0; i < len; i++)
        n += text[i] == '\n';
    free(text);
    return n;
}
