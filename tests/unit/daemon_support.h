/* Helpers for the daemon's tests: scratch directories and small files. */
#ifndef UWB_DAEMON_SUPPORT_H
#define UWB_DAEMON_SUPPORT_H

#include <stddef.h>

/* A fresh directory under /tmp (mkdtemp); fails the test if it cannot. */
void dtest_scratch_dir(char *path, size_t n, const char *tag);
/* rm -r */
void dtest_remove_tree(const char *path);
/* Whole file into a malloc'd NUL-terminated buffer, NULL if unreadable. */
char *dtest_slurp(const char *path, size_t *len);
/* Write text to path (not atomically: for setting up test states). */
void dtest_spit(const char *path, const char *text);
int dtest_file_exists(const char *path);
/* Lines in a file (count of '\n'). */
int dtest_count_lines(const char *path);

#endif
