/* Reading a whole file (or what a descriptor gives up to EOF) into memory,
 * refused beyond a size the caller names, so a wrong path or a runaway
 * input cannot make us allocate without bound. */
#ifndef UWB_READ_FILE_H
#define UWB_READ_FILE_H

#include <stddef.h>

enum uwb_read_result {
    UWB_READ_OK = 0,
    UWB_READ_FAILED = -1,  /* cannot open, stat or read, or out of memory */
    UWB_READ_TOO_BIG = -2, /* more than max_bytes */
};

/* The file's bytes in a malloc'd buffer with a NUL after the last one (not
 * counted in *out_len), so text callers can use it as a string. On failure
 * *out is NULL, *out_len 0 and err holds "PATH: problem". Only a regular
 * file is read (uwb_open_regular): a FIFO, socket or device is refused at
 * once, never waited on; read those through uwb_read_fd. */
enum uwb_read_result uwb_read_file(const char *path, size_t max_bytes, char **out, size_t *out_len, char *err,
                                   size_t errlen);

/* The same, refusing a symbolic link too: for files in the state directory. */
enum uwb_read_result uwb_read_file_nofollow(const char *path, size_t max_bytes, char **out, size_t *out_len,
                                            char *err, size_t errlen);

/* The same for an open descriptor (stdin, a pipe), read to EOF and left
 * open; name stands for it in messages. */
enum uwb_read_result uwb_read_fd(int fd, const char *name, size_t max_bytes, char **out, size_t *out_len,
                                 char *err, size_t errlen);

#endif
