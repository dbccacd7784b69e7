/* Log lines with a level, to stderr (journald keeps the level when it is
 * the reader) and optionally to syslog. One write() per line, so lines
 * from the scan thread and the main loop never interleave. */
#ifndef UWB_UTIL_LOG_H
#define UWB_UTIL_LOG_H

/* syslog priorities */
enum uwbd_log_level {
    UWBD_LOG_ERR = 3,
    UWBD_LOG_WARNING = 4,
    UWBD_LOG_NOTICE = 5,
    UWBD_LOG_INFO = 6,
    UWBD_LOG_DEBUG = 7,
};

/* max_level: lines above it are dropped (default UWBD_LOG_INFO). Call once
 * at start, before any thread exists. */
void uwbd_log_setup(int max_level, int use_syslog);
void uwbd_log(int level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
