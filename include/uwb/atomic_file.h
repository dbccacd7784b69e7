/* Files that appear whole or not at all: write to a temporary sibling,
 * fsync it, rename it over the target, fsync the directory. */
#ifndef UWB_ATOMIC_FILE_H
#define UWB_ATOMIC_FILE_H

#include <stdio.h>
#include <stddef.h>

struct atomic_file {
    FILE *fp;
    char final_path[4096];
    char temp_path[4096];
};

/* Temporaries are named ATOMIC_FILE_TEMP_PREFIX "<name>.XXXXXX"
 * ATOMIC_FILE_TEMP_SUFFIX, a name nothing else makes, so a start-up cleanup
 * can tell a crash's leftover from someone else's file. */
#define ATOMIC_FILE_TEMP_PREFIX ".uwbd-tmp."
#define ATOMIC_FILE_TEMP_SUFFIX ".part"

/* 1 when `name` (no directory) is one of our temporaries. */
int uwb_atomic_file_is_temporary_name(const char *name);

/* Open a temporary file beside `path`. Returns 0, or -1 with err filled. */
int uwb_atomic_file_open(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Flush, fsync, rename over the final path, fsync the directory. On any
 * failure the temporary is removed and the old target is untouched. */
int uwb_atomic_file_commit(struct atomic_file *af, char *err, size_t errlen);
/* Discard the temporary; the target is untouched. */
void uwb_atomic_file_abort(struct atomic_file *af);

/* One-shot convenience. */
int uwb_atomic_write_file(const char *path, const void *data, size_t len, char *err, size_t errlen);

#endif
