/* Levelled log lines to stderr and, when asked, syslog. */
#include "util/log.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <syslog.h>
#include <unistd.h>

static int log_max_level = UWBD_LOG_INFO;
static int log_to_syslog;
static int stderr_is_journal;

/* systemd sets JOURNAL_STREAM to "DEV:INODE" of the stream it connected to
 * stderr; lines starting "<N>" there keep their priority. */
static int detect_journal(void)
{
    const char *js = getenv("JOURNAL_STREAM");
    struct stat st;
    if (!js || js[0] < '0' || js[0] > '9')
        return 0;
    char *colon, *end;
    errno = 0;
    unsigned long long dev = strtoull(js, &colon, 10);
    if (errno || *colon != ':' || colon[1] < '0' || colon[1] > '9')
        return 0;
    unsigned long long ino = strtoull(colon + 1, &end, 10);
    if (errno || *end != '\0' || fstat(STDERR_FILENO, &st) != 0)
        return 0;
    return (unsigned long long)st.st_dev == dev && (unsigned long long)st.st_ino == ino;
}

void uwbd_log_setup(int max_level, int use_syslog)
{
    log_max_level = max_level;
    stderr_is_journal = detect_journal();
    log_to_syslog = use_syslog && !stderr_is_journal; /* never the same line twice in the journal */
    if (log_to_syslog)
        openlog("uwbd", LOG_PID, LOG_DAEMON);
}

static const char *level_name(int level)
{
    switch (level) {
    case UWBD_LOG_ERR: return "error";
    case UWBD_LOG_WARNING: return "warning";
    case UWBD_LOG_NOTICE: return "notice";
    case UWBD_LOG_INFO: return "info";
    default: return "debug";
    }
}

void uwbd_log(int level, const char *fmt, ...)
{
    if (level > log_max_level)
        return;
    char message[1536];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    char line[1600];
    int n = stderr_is_journal ? snprintf(line, sizeof line, "<%d>%s\n", level, message)
                              : snprintf(line, sizeof line, "uwbd: %s: %s\n", level_name(level), message);
    if (n > (int)sizeof line - 1) {
        n = (int)sizeof line - 1;
        line[n - 1] = '\n';
    }
    if (n > 0 && write(STDERR_FILENO, line, (size_t)n) < 0) {
        /* Nowhere else to report it. */
    }
    if (log_to_syslog)
        syslog(level, "%s", message);
}
