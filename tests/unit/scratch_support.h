/* Helpers for tests that touch the file system: scratch directories and small files. */
#ifndef UWB_SCRATCH_SUPPORT_H
#define UWB_SCRATCH_SUPPORT_H

#include <stddef.h>

/* A fresh directory under /tmp (mkdtemp); fails the test if it cannot. */
void scratch_scratch_dir(char *path, size_t n, const char *tag);
/* rm -r; 0 when path is gone afterwards, -1 if something stayed. */
int scratch_remove_tree(const char *path);
/* Whole file into a malloc'd NUL-terminated buffer, NULL if unreadable or over 64 MiB. */
char *scratch_slurp(const char *path, size_t *len);
/* Fails the test unless path holds exactly the len bytes of expected. */
void scratch_assert_file_holds(const char *path, const char *expected, size_t len);
/* Write text to path (not atomically: for setting up test states). */
void scratch_spit(const char *path, const char *text);
int scratch_file_exists(const char *path);
/* Lines in a file (count of '\n'). */
int scratch_count_lines(const char *path);

#endif
