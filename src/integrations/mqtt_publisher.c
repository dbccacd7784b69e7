/* MQTT publishing through libmosquitto, driven by a network thread of our
 * own (see the header). The queue is shared with that thread's callbacks:
 * one mutex guards it; the callbacks only publish and unlink, never block.
 * The thread is ours, not mosquitto_loop_start's, because that one ends
 * silently for good after a failed TLS handshake, and retries a refused
 * or unreachable broker without a word: here every attempt's outcome is
 * seen, each kind of failure logged once, and `status` shows the link. */
#include "integrations/mqtt_publisher.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <netdb.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "uwb/atomic_file.h"
#include "util/log.h"
#include "integrations/mosquitto_loader.h"
#include "uwb/link.h"
#include "uwb/read_file.h"

#define KEEPALIVE_S 60
/* An attempt that has not connected by then has failed (a broker that
 * drops the packets, a half-open TLS port). */
#define CONNECT_TIMEOUT_S 10
/* How long one mosquitto_loop call waits: also how soon a stop is seen. */
#define LOOP_MS 100
/* The sentinel for an attempt that timed out (not a libmosquitto code). */
#define LINK_TIMED_OUT (-1000)
/* The broker closed the connection in the TLS handshake (not a libmosquitto code). */
#define LINK_CLOSED_IN_HANDSHAKE (-1001)
#define QOS 1
#define CLOSE_WAIT_MS 2000
#define QUEUE_DIR "mqtt-queue"
#define VERDICT_MAX ((size_t)1024 * 1024)
/* Commands waiting for the main loop; more are refused, not queued. */
#define COMMANDS_MAX 8

struct uwbd_mqtt {
    const struct uwbd_mosquitto_api *lib; /* libmosquitto, loaded (mosquitto_loader.h) */
    struct mosquitto *mosq;
    pthread_mutex_t lock;
    char dir[UWBD_SITE_PATH_MAX + 32];
    char verdict_topic[256], status_topic[256];
    int queue_max;
    unsigned long long *queue; /* sequence numbers of the files waiting, oldest first */
    size_t queued, cap;
    unsigned long long next_seq;
    int connected;
    int inflight_mid; /* the queue head's publish, 0 = none */
    int offline_mid, offline_acked;
    int was_connected; /* log a lost broker once */
    /* The network thread and what it says about the link (under lock). */
    pthread_t thread;
    int thread_started;
    int closing, stopping; /* close(): say goodbye, then end the thread */
    int thread_done;
    char host[256];
    int port;
    char endpoint[UWB_ENDPOINT_MAX];
    int tls;
    double reconnect_max_s;
    int failing; /* the last attempt failed: reason says why */
    char reason[512];
    unsigned logged; /* a bit per failure kind logged since the last connection */
    int refused_rc;  /* this attempt's CONNACK refusal, -1 none */
    /* libmosquitto's latest error log line this attempt (OpenSSL's reason
     * for a failed handshake). Its own lock: libmosquitto logs from inside
     * calls the main thread makes holding `lock`. */
    pthread_mutex_t error_lock;
    char lib_error[256];
    char cmd_topic[256], reply_topic[256];
    char health_topic[256];
    cJSON *health;                /* the latest health report, sent on every connection */
    int command_fd;               /* eventfd: commands wait; -1 without mqtt.commands */
    char *commands[COMMANDS_MAX]; /* received, not yet taken by the main loop */
    size_t n_commands;
};

static void file_of(const struct uwbd_mqtt *m, unsigned long long seq, char *path, size_t n)
{
    snprintf(path, n, "%s/%020llu.json", m->dir, seq);
}

/* Publishes the queue's head unless one is on its way. Called locked. */
static void send_next(struct uwbd_mqtt *m)
{
    if (!m->connected || m->inflight_mid || !m->queued)
        return;
    char path[sizeof m->dir + 32], err[512];
    file_of(m, m->queue[0], path, sizeof path);
    char *text;
    size_t len;
    if (uwb_read_file_nofollow(path, VERDICT_MAX, &text, &len, err, sizeof err) != UWB_READ_OK) {
        uwbd_log(UWBD_LOG_ERR, "mqtt: queued verdict %s: %s; dropped", path, err);
        unlink(path);
        memmove(m->queue, m->queue + 1, (size_t)(m->queued - 1) * sizeof *m->queue);
        m->queued--;
        send_next(m);
        return;
    }
    int mid = 0;
    int rc = m->lib->publish(m->mosq, &mid, m->verdict_topic, (int)len, text, QOS, true);
    free(text);
    if (rc == MOSQ_ERR_SUCCESS)
        m->inflight_mid = mid;
    else
        uwbd_log(UWBD_LOG_WARNING, "mqtt: publish: %s (tried again on reconnecting)", m->lib->strerror(rc));
}

/* Publishes the health report with its "mqtt_queued" set to the verdicts
 * waiting now: the daemon's count, taken while its verdict was still on
 * its way, is stale once the broker has it. Called locked. */
static void send_health(struct uwbd_mqtt *m)
{
    if (!m->connected || !m->health)
        return;
    cJSON *queued = cJSON_GetObjectItemCaseSensitive(m->health, "mqtt_queued");
    if (cJSON_IsNumber(queued))
        cJSON_SetNumberValue(queued, (double)m->queued);
    char *text = cJSON_PrintUnformatted(m->health);
    if (text)
        m->lib->publish(m->mosq, NULL, m->health_topic, (int)strlen(text), text, QOS, true);
    free(text);
}

static void on_connect(struct mosquitto *mosq, void *ctx, int rc)
{
    struct uwbd_mqtt *m = ctx;
    pthread_mutex_lock(&m->lock);
    if (rc != 0) { /* logged by the network thread, once */
        m->refused_rc = rc;
        pthread_mutex_unlock(&m->lock);
        return;
    }
    m->connected = 1;
    m->was_connected = 1;
    m->failing = 0;
    m->reason[0] = '\0';
    m->logged = 0;
    m->inflight_mid = 0; /* a publish cut off by the disconnection is sent again: at least once */
    m->lib->publish(mosq, NULL, m->status_topic, 6, "online", QOS, true);
    if (m->command_fd >= 0)
        m->lib->subscribe(mosq, NULL, m->cmd_topic, QOS);
    send_health(m);
    uwbd_log(UWBD_LOG_NOTICE, "mqtt: connected; %zu verdict(s) queued", m->queued);
    send_next(m);
    pthread_mutex_unlock(&m->lock);
}

static void on_disconnect(struct mosquitto *mosq, void *ctx, int rc)
{
    (void)mosq;
    struct uwbd_mqtt *m = ctx;
    pthread_mutex_lock(&m->lock);
    if (m->connected && rc != 0)
        uwbd_log(UWBD_LOG_WARNING, "mqtt: connection lost (%s); verdicts are queued until it is back",
                 m->lib->strerror(rc));
    m->connected = 0;
    pthread_mutex_unlock(&m->lock);
}

static void on_log(struct mosquitto *mosq, void *ctx, int level, const char *text)
{
    (void)mosq;
    struct uwbd_mqtt *m = ctx;
    if (!(level & MOSQ_LOG_ERR) || !text)
        return;
    pthread_mutex_lock(&m->error_lock);
    snprintf(m->lib_error, sizeof m->lib_error, "%s", text);
    pthread_mutex_unlock(&m->error_lock);
}

static void on_publish(struct mosquitto *mosq, void *ctx, int mid)
{
    (void)mosq;
    struct uwbd_mqtt *m = ctx;
    pthread_mutex_lock(&m->lock);
    if (mid == m->offline_mid)
        m->offline_acked = 1;
    if (mid == m->inflight_mid && m->queued) {
        char path[sizeof m->dir + 32];
        file_of(m, m->queue[0], path, sizeof path);
        unlink(path);
        memmove(m->queue, m->queue + 1, (m->queued - 1) * sizeof *m->queue);
        m->queued--;
        m->inflight_mid = 0;
        send_next(m);
        send_health(m); /* its queue count, one fewer */
    }
    pthread_mutex_unlock(&m->lock);
}

static void on_message(struct mosquitto *mosq, void *ctx, const struct mosquitto_message *msg)
{
    struct uwbd_mqtt *m = ctx;
    if (msg->retain)
        return; /* a command left on the broker is stale by the time it is read */
    pthread_mutex_lock(&m->lock);
    char *text = NULL;
    if (m->n_commands < COMMANDS_MAX && msg->payloadlen >= 0 && msg->payloadlen <= 256 &&
        (text = malloc((size_t)msg->payloadlen + 1))) {
        memcpy(text, msg->payload, (size_t)msg->payloadlen);
        text[msg->payloadlen] = '\0';
        m->commands[m->n_commands++] = text;
        uint64_t one = 1;
        if (write(m->command_fd, &one, sizeof one) != sizeof one) {
            /* the counter is full: the loop has a wake-up pending anyway */
        }
    } else {
        const char *busy =
            "{\"class\":\"ERROR\",\"message\":\"too many commands waiting, or one over 256 bytes\"}";
        m->lib->publish(mosq, NULL, m->reply_topic, (int)strlen(busy), busy, QOS, false);
    }
    pthread_mutex_unlock(&m->lock);
}

static int push_seq(struct uwbd_mqtt *m, unsigned long long seq)
{
    if (m->queued == m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 64;
        unsigned long long *q = realloc(m->queue, cap * sizeof *q);
        if (!q)
            return -1;
        m->queue = q;
        m->cap = cap;
    }
    m->queue[m->queued++] = seq;
    return 0;
}

static int compare_seq(const void *a, const void *b)
{
    unsigned long long x = *(const unsigned long long *)a, y = *(const unsigned long long *)b;
    return x < y ? -1 : x > y;
}

/* The queue left by an earlier run, oldest first. */
static int load_queue(struct uwbd_mqtt *m, char *err, size_t errlen)
{
    if (mkdir(m->dir, 0750) != 0 && errno != EEXIST) {
        snprintf(err, errlen, "mqtt: queue directory %s: %s", m->dir, strerror(errno));
        return -1;
    }
    DIR *d = opendir(m->dir);
    if (!d) {
        snprintf(err, errlen, "mqtt: queue directory %s: %s", m->dir, strerror(errno));
        return -1;
    }
    for (struct dirent *e; (e = readdir(d));) {
        /* NNNNNNNNNNNNNNNNNNNN.json: 20 digits, the sequence number */
        char *end;
        errno = 0;
        unsigned long long seq = strtoull(e->d_name, &end, 10);
        if (strlen(e->d_name) == 25 && isdigit((unsigned char)e->d_name[0]) && end == e->d_name + 20 &&
            errno == 0 && strcmp(end, ".json") == 0)
            if (push_seq(m, seq) != 0)
                break;
    }
    closedir(d);
    if (m->queued) /* qsort may not be given NULL, even for none */
        qsort(m->queue, m->queued, sizeof *m->queue, compare_seq);
    m->next_seq = m->queued ? m->queue[m->queued - 1] + 1 : 1;
    return 0;
}

static int read_password(const char *path, char *out, size_t n, char *err, size_t errlen)
{
    char *text;
    size_t len;
    if (uwb_read_file(path, 4096, &text, &len, err, errlen) != UWB_READ_OK)
        return -1;
    size_t line = strcspn(text, "\r\n");
    if (line == 0 || line >= n) {
        snprintf(err, errlen, "mqtt.password_file %s: the first line must hold the password (1..%zu bytes)",
                 path, n - 1);
        free(text);
        return -1;
    }
    memcpy(out, text, line);
    out[line] = '\0';
    memset(text, 0, len);
    free(text);
    return 0;
}

/* libmosquitto says only "invalid function arguments" for a TLS file it
 * cannot read (one gone or unreadable since the config was checked): name
 * the file and its key. */
static void tls_error(const struct uwbd_mqtt *m, const struct uwbd_site_config *cfg, int rc, char *err,
                      size_t errlen)
{
    const struct {
        const char *key, *path;
    } files[] = {
        {"mqtt.ca_file", cfg->mqtt_ca_file},
        {"mqtt.cert_file", cfg->mqtt_cert_file},
        {"mqtt.key_file", cfg->mqtt_key_file},
    };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        if (files[i].path[0] && access(files[i].path, R_OK) != 0) {
            snprintf(err, errlen, "%s %s: %s", files[i].key, files[i].path, strerror(errno));
            return;
        }
    }
    snprintf(err, errlen, "mqtt.ca_file %s: libmosquitto refused the TLS files: %s", cfg->mqtt_ca_file,
             m->lib->strerror(rc));
}

static int configure(struct uwbd_mqtt *m, const struct uwbd_site_config *cfg, char *err, size_t errlen)
{
    m->lib->connect_callback_set(m->mosq, on_connect);
    m->lib->disconnect_callback_set(m->mosq, on_disconnect);
    m->lib->publish_callback_set(m->mosq, on_publish);
    m->lib->message_callback_set(m->mosq, on_message);
    m->lib->log_callback_set(m->mosq, on_log);
    int rc = m->lib->will_set(m->mosq, m->status_topic, 7, "offline", QOS, true);
    if (rc == MOSQ_ERR_SUCCESS && cfg->mqtt_username[0]) {
        char password[512];
        if (read_password(cfg->mqtt_password_file, password, sizeof password, err, errlen) != 0)
            return -1;
        rc = m->lib->username_pw_set(m->mosq, cfg->mqtt_username, password);
        memset(password, 0, sizeof password);
    }
    if (rc == MOSQ_ERR_SUCCESS && cfg->mqtt_ca_file[0]) {
        rc = m->lib->tls_set(m->mosq, cfg->mqtt_ca_file, NULL,
                             cfg->mqtt_cert_file[0] ? cfg->mqtt_cert_file : NULL,
                             cfg->mqtt_key_file[0] ? cfg->mqtt_key_file : NULL, NULL);
        if (rc != MOSQ_ERR_SUCCESS) {
            tls_error(m, cfg, rc, err, errlen);
            return -1;
        }
    }
    if (rc == MOSQ_ERR_SUCCESS)
        rc = m->lib->threaded_set(m->mosq, true); /* our network thread, not mosquitto_loop_start's */
    if (rc != MOSQ_ERR_SUCCESS) {
        snprintf(err, errlen, "mqtt: %s", m->lib->strerror(rc));
        return -1;
    }
    return 0;
}

/* ---- the network thread ------------------------------------------------- */

enum failure_kind { FAILURE_TLS, FAILURE_REFUSED, FAILURE_UNREACHABLE };

static int flag(struct uwbd_mqtt *m, const int *which)
{
    pthread_mutex_lock(&m->lock);
    int v = *which;
    pthread_mutex_unlock(&m->lock);
    return v;
}

static double seconds_since(const struct timespec *t)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - t->tv_sec) + (double)(now.tv_nsec - t->tv_nsec) * 1e-9;
}

/* A TCP connection to the broker, non-blocking and bounded by the time
 * left of the attempt: 0 when it connects, else the errno that ended it
 * (ETIMEDOUT when the deadline passed first). */
static int probe_tcp(const struct uwbd_mqtt *m, double seconds)
{
    char port[16];
    snprintf(port, sizeof port, "%d", m->port);
    struct addrinfo hints = {.ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM}, *found;
    if (getaddrinfo(m->host, port, &hints, &found) != 0)
        return EHOSTUNREACH;
    int err_no = ECONNREFUSED;
    for (struct addrinfo *a = found; a; a = a->ai_next) {
        int fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) {
            err_no = errno;
            continue;
        }
        if (connect(fd, a->ai_addr, a->ai_addrlen) == 0) {
            err_no = 0;
        } else if (errno != EINPROGRESS) {
            err_no = errno;
        } else {
            struct pollfd p = {.fd = fd, .events = POLLOUT};
            int ready = poll(&p, 1, (int)(seconds * 1e3));
            socklen_t len = sizeof err_no;
            if (ready <= 0)
                err_no = ETIMEDOUT;
            else if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &err_no, &len) != 0)
                err_no = errno;
        }
        close(fd);
        if (err_no == 0)
            break;
    }
    freeaddrinfo(found);
    return err_no;
}

/* With TLS, libmosquitto takes a TCP connection that failed for a handshake
 * still under way (OpenSSL's SSL_ERROR_SYSCALL means "try again" to it) and
 * would wait out CONNECT_TIMEOUT_S in silence: a hung-up socket before the
 * CONNACK is that failure. Its errno is gone (the handshake's write read
 * it), so a probe of our own asks the broker's port again. 0: no failure
 * seen; else the errno (*err_no) or LINK_CLOSED_IN_HANDSHAKE. */
static int tls_connect_failure(struct uwbd_mqtt *m, double seconds_left, int *err_no)
{
    int fd = m->lib->socket(m->mosq);
    struct pollfd p = {.fd = fd, .events = POLLOUT};
    if (fd < 0 || poll(&p, 1, 0) != 1 || !(p.revents & (POLLERR | POLLHUP)))
        return 0;
    int so_error = 0;
    socklen_t len = sizeof so_error;
    if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &so_error, &len) != 0 || so_error == 0)
        so_error = probe_tcp(m, seconds_left > 0 ? seconds_left : 0);
    if (so_error == 0)
        return LINK_CLOSED_IN_HANDSHAKE;
    *err_no = so_error;
    return so_error == ETIMEDOUT ? LINK_TIMED_OUT : MOSQ_ERR_ERRNO;
}

/* Runs one connection until it ends: the libmosquitto code that ended it,
 * LINK_TIMED_OUT, LINK_CLOSED_IN_HANDSHAKE, or MOSQ_ERR_SUCCESS when
 * stopped. *was_up: it connected. *err_no: the errno of a failed connect. */
static int run_link(struct uwbd_mqtt *m, int *was_up, int *err_no)
{
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    *was_up = 0;
    for (;;) {
        if (flag(m, &m->stopping))
            return MOSQ_ERR_SUCCESS;
        int rc = m->lib->loop(m->mosq, LOOP_MS, 1);
        *err_no = errno;
        if (flag(m, &m->connected))
            *was_up = 1;
        if (rc != MOSQ_ERR_SUCCESS)
            return rc;
        if (*was_up || flag(m, &m->closing))
            continue;
        if (m->tls && (rc = tls_connect_failure(m, CONNECT_TIMEOUT_S - seconds_since(&start), err_no)) != 0)
            return rc;
        if (seconds_since(&start) > CONNECT_TIMEOUT_S)
            return LINK_TIMED_OUT;
    }
}

/* Why an attempt that never connected failed, and its kind. */
static enum failure_kind classify(struct uwbd_mqtt *m, int rc, int err_no, char *why, size_t n)
{
    char lib_error[sizeof m->lib_error];
    pthread_mutex_lock(&m->error_lock);
    snprintf(lib_error, sizeof lib_error, "%s", m->lib_error);
    pthread_mutex_unlock(&m->error_lock);
    int refused = flag(m, &m->refused_rc);
    if (refused >= 0) {
        snprintf(why, n, "refused by the broker: %s (CONNACK code %d)", m->lib->connack_string(refused),
                 refused);
        return FAILURE_REFUSED;
    }
    if (m->tls && rc != LINK_TIMED_OUT &&
        (rc == MOSQ_ERR_TLS || rc == LINK_CLOSED_IN_HANDSHAKE || strstr(lib_error, "SSL") ||
         (rc == MOSQ_ERR_ERRNO && err_no == EPROTO))) {
        snprintf(why, n, "TLS handshake failed: %s (is the broker's port TLS? mqtt.ca_file turns TLS on)",
                 lib_error[0]                     ? lib_error
                 : rc == LINK_CLOSED_IN_HANDSHAKE ? "the broker closed the connection"
                                                  : m->lib->strerror(rc));
        return FAILURE_TLS;
    }
    if (rc == LINK_TIMED_OUT)
        snprintf(why, n, "no connection within %d s (unreachable, or the packets are dropped)",
                 CONNECT_TIMEOUT_S);
    else
        snprintf(why, n, "unreachable: %s",
                 rc == MOSQ_ERR_ERRNO && err_no ? strerror(err_no)
                 : lib_error[0]                 ? lib_error
                                                : m->lib->strerror(rc));
    return FAILURE_UNREACHABLE;
}

/* A failed attempt: its reason for `status`, and the log once per kind
 * until the link is up again (a retry every few seconds says nothing new). */
static void note_failure(struct uwbd_mqtt *m, int rc, int err_no)
{
    char why[sizeof m->reason];
    enum failure_kind kind = classify(m, rc, err_no, why, sizeof why);
    pthread_mutex_lock(&m->lock);
    m->failing = 1;
    snprintf(m->reason, sizeof m->reason, "%s", why);
    if (!(m->logged & (1u << kind))) {
        m->logged |= 1u << kind;
        uwbd_log(UWBD_LOG_WARNING, "mqtt: %s: %s; %zu verdict(s) queued, trying again every %g s at most",
                 m->endpoint, why, m->queued, m->reconnect_max_s);
    }
    pthread_mutex_unlock(&m->lock);
}

/* Sleeps `seconds` in steps, back early when asked to close. */
static void back_off(struct uwbd_mqtt *m, double seconds)
{
    long steps = (long)(seconds * 1e3 / LOOP_MS + 0.5);
    for (long i = 0; i < steps; i++) {
        if (flag(m, &m->closing) || flag(m, &m->stopping))
            return;
        nanosleep(&(struct timespec){.tv_nsec = LOOP_MS * 1000000L}, NULL);
    }
}

static void *network_main(void *arg)
{
    struct uwbd_mqtt *m = arg;
    double delay_s = 1.0;
    for (int attempt = 0; !flag(m, &m->closing) && !flag(m, &m->stopping); attempt++) {
        pthread_mutex_lock(&m->lock);
        m->refused_rc = -1;
        pthread_mutex_unlock(&m->lock);
        pthread_mutex_lock(&m->error_lock);
        m->lib_error[0] = '\0';
        pthread_mutex_unlock(&m->error_lock);
        errno = 0;
        int rc = attempt == 0 ? m->lib->connect_async(m->mosq, m->host, m->port, KEEPALIVE_S)
                              : m->lib->reconnect_async(m->mosq);
        int err_no = errno, was_up = 0;
        if (rc == MOSQ_ERR_SUCCESS)
            rc = run_link(m, &was_up, &err_no);
        if (flag(m, &m->closing) || flag(m, &m->stopping))
            break;
        if (was_up) /* the loss is on_disconnect's to log */
            delay_s = 1.0;
        else
            note_failure(m, rc, err_no);
        back_off(m, delay_s);
        delay_s = delay_s * 2 < m->reconnect_max_s ? delay_s * 2 : m->reconnect_max_s;
        if (delay_s < 1.0)
            delay_s = 1.0;
    }
    /* Closing: let libmosquitto send its DISCONNECT, briefly. */
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    while (!flag(m, &m->stopping) && seconds_since(&start) < 1.0 &&
           m->lib->loop(m->mosq, LOOP_MS, 1) == MOSQ_ERR_SUCCESS) {
    }
    pthread_mutex_lock(&m->lock);
    m->thread_done = 1;
    pthread_mutex_unlock(&m->lock);
    return NULL;
}

/* The publisher's names and limits, from its config; acquires nothing. */
static void set_names(struct uwbd_mqtt *m, const struct uwbd_site_config *cfg, const struct uwb_endpoint *ep,
                      const char *state_dir)
{
    m->refused_rc = -1;
    snprintf(m->host, sizeof m->host, "%s", ep->host);
    m->port = (int)strtol(ep->port, NULL, 10);
    snprintf(m->endpoint, sizeof m->endpoint, "%s", cfg->mqtt_endpoint);
    m->tls = cfg->mqtt_ca_file[0] != '\0';
    m->reconnect_max_s = cfg->mqtt_reconnect_max_s;
    snprintf(m->dir, sizeof m->dir, "%s/" QUEUE_DIR, state_dir);
    snprintf(m->verdict_topic, sizeof m->verdict_topic, "%s/%s/verdict", cfg->mqtt_topic_prefix,
             cfg->asset_id);
    snprintf(m->status_topic, sizeof m->status_topic, "%s/%s/status", cfg->mqtt_topic_prefix, cfg->asset_id);
    m->queue_max = cfg->mqtt_queue_max;
    snprintf(m->cmd_topic, sizeof m->cmd_topic, "%s/%s/cmd", cfg->mqtt_topic_prefix, cfg->asset_id);
    snprintf(m->reply_topic, sizeof m->reply_topic, "%s/%s/reply", cfg->mqtt_topic_prefix, cfg->asset_id);
    snprintf(m->health_topic, sizeof m->health_topic, "%s/%s/health", cfg->mqtt_topic_prefix, cfg->asset_id);
}

/* Acquires all or none: the endpoint and the library are checked before
 * anything is held; from the allocation on, every failure goes to `fail`,
 * where close() releases whatever was acquired so far (it takes a
 * publisher at any stage: no mosq, no thread, no eventfd). */
int uwbd_mqtt_open(struct uwbd_mqtt **out, const struct uwbd_site_config *cfg, const char *state_dir,
                   char *err, size_t errlen)
{
    *out = NULL;
    struct uwb_endpoint ep;
    char why[256];
    if (uwb_endpoint_parse(cfg->mqtt_endpoint, &ep, why, sizeof why) != UWB_LINK_OK) {
        snprintf(err, errlen, "mqtt.endpoint: %s", why);
        return -1;
    }
    /* Before anything else: an MQTT site without the library is told so at start. */
    const struct uwbd_mosquitto_api *lib = uwbd_mosquitto_load(err, errlen);
    if (!lib)
        return -1;
    struct uwbd_mqtt *m = calloc(1, sizeof *m);
    if (!m) {
        snprintf(err, errlen, "mqtt: out of memory");
        return -1;
    }
    m->lib = lib;
    m->command_fd = -1;
    pthread_mutex_init(&m->lock, NULL);
    pthread_mutex_init(&m->error_lock, NULL);
    m->lib->lib_init(); /* close() ends with its cleanup */
    set_names(m, cfg, &ep, state_dir);
    if (cfg->mqtt_commands && (m->command_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) < 0) {
        snprintf(err, errlen, "mqtt: eventfd: %s", strerror(errno));
        goto fail;
    }
    char client_id[128];
    snprintf(client_id, sizeof client_id, "uwbd-%s", cfg->asset_id);
    m->mosq = m->lib->new (client_id, true, m);
    if (!m->mosq) {
        snprintf(err, errlen, "mqtt: out of memory");
        goto fail;
    }
    if (load_queue(m, err, errlen) != 0 || configure(m, cfg, err, errlen) != 0)
        goto fail;
    int rc = pthread_create(&m->thread, NULL, network_main, m);
    if (rc != 0) {
        snprintf(err, errlen, "mqtt: cannot start its thread: %s", strerror(rc));
        goto fail;
    }
    m->thread_started = 1;
    uwbd_log(UWBD_LOG_INFO, "mqtt: publishing to %s on %s (%zu verdict(s) queued from before)",
             m->verdict_topic, cfg->mqtt_endpoint, m->queued);
    *out = m;
    return 0;
fail:
    uwbd_mqtt_close(m);
    return -1;
}

void uwbd_mqtt_verdict(struct uwbd_mqtt *m, const char *verdict_json)
{
    if (!m || !verdict_json)
        return;
    pthread_mutex_lock(&m->lock);
    char path[sizeof m->dir + 32], err[512];
    unsigned long long seq = m->next_seq++;
    file_of(m, seq, path, sizeof path);
    if (uwb_atomic_write_file(path, verdict_json, strlen(verdict_json), err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "mqtt: cannot queue the verdict: %s", err);
    } else if (push_seq(m, seq) != 0) {
        unlink(path);
        uwbd_log(UWBD_LOG_ERR, "mqtt: out of memory for the queue");
    }
    /* Bounded: the oldest waiting (not the one on its way) makes room. */
    while ((int)m->queued > m->queue_max) {
        size_t victim = m->inflight_mid ? 1 : 0;
        file_of(m, m->queue[victim], path, sizeof path);
        unlink(path);
        uwbd_log(UWBD_LOG_WARNING, "mqtt: queue full (mqtt.queue_max %d): the oldest queued verdict dropped",
                 m->queue_max);
        memmove(m->queue + victim, m->queue + victim + 1, (m->queued - victim - 1) * sizeof *m->queue);
        m->queued--;
    }
    send_next(m);
    pthread_mutex_unlock(&m->lock);
}

int uwbd_mqtt_command_fd(const struct uwbd_mqtt *m)
{
    return m ? m->command_fd : -1;
}

char *uwbd_mqtt_next_command(struct uwbd_mqtt *m)
{
    if (!m || m->command_fd < 0)
        return NULL;
    pthread_mutex_lock(&m->lock);
    char *text = NULL;
    if (m->n_commands) {
        text = m->commands[0];
        memmove(m->commands, m->commands + 1, (m->n_commands - 1) * sizeof *m->commands);
        m->n_commands--;
    }
    if (!m->n_commands) {
        uint64_t count;
        if (read(m->command_fd, &count, sizeof count) < 0) {
            /* nothing to drain */
        }
    }
    pthread_mutex_unlock(&m->lock);
    return text;
}

void uwbd_mqtt_reply(struct uwbd_mqtt *m, const char *reply_json)
{
    if (m && reply_json)
        m->lib->publish(m->mosq, NULL, m->reply_topic, (int)strlen(reply_json), reply_json, QOS, false);
}

void uwbd_mqtt_health(struct uwbd_mqtt *m, const char *health_json)
{
    if (!m || !health_json)
        return;
    cJSON *report = cJSON_Parse(health_json);
    if (!report)
        uwbd_log(UWBD_LOG_ERR, "mqtt: the health report is not JSON; the previous one stays");
    pthread_mutex_lock(&m->lock);
    if (report) {
        cJSON_Delete(m->health);
        m->health = report;
    }
    send_health(m);
    pthread_mutex_unlock(&m->lock);
}

size_t uwbd_mqtt_queued(struct uwbd_mqtt *m)
{
    pthread_mutex_lock(&m->lock);
    size_t n = m->queued;
    pthread_mutex_unlock(&m->lock);
    return n;
}

void uwbd_mqtt_link(struct uwbd_mqtt *m, struct uwbd_mqtt_link *out)
{
    pthread_mutex_lock(&m->lock);
    out->state = m->connected ? "connected" : m->failing ? "failing" : "connecting";
    snprintf(out->reason, sizeof out->reason, "%s", m->connected ? "" : m->reason);
    out->queued = m->queued;
    pthread_mutex_unlock(&m->lock);
}

void uwbd_mqtt_close(struct uwbd_mqtt *m)
{
    if (!m)
        return;
    if (m->mosq) {
        pthread_mutex_lock(&m->lock);
        int connected = m->connected;
        if (connected)
            m->lib->publish(m->mosq, &m->offline_mid, m->status_topic, 7, "offline", QOS, true);
        pthread_mutex_unlock(&m->lock);
        for (int waited = 0; connected && waited < CLOSE_WAIT_MS; waited += 10) {
            pthread_mutex_lock(&m->lock);
            int done = m->offline_acked;
            pthread_mutex_unlock(&m->lock);
            if (done)
                break;
            nanosleep(&(struct timespec){.tv_nsec = 10000000L}, NULL);
        }
        pthread_mutex_lock(&m->lock);
        m->closing = 1;
        pthread_mutex_unlock(&m->lock);
        m->lib->disconnect(m->mosq);
        /* The thread sends the DISCONNECT (a second at most), then ends. */
        for (int waited = 0; m->thread_started && !flag(m, &m->thread_done) && waited < CLOSE_WAIT_MS;
             waited += 10)
            nanosleep(&(struct timespec){.tv_nsec = 10000000L}, NULL);
        pthread_mutex_lock(&m->lock);
        m->stopping = 1;
        pthread_mutex_unlock(&m->lock);
        if (m->thread_started)
            pthread_join(m->thread, NULL);
        m->lib->destroy(m->mosq);
    }
    m->lib->lib_cleanup();
    pthread_mutex_destroy(&m->lock);
    pthread_mutex_destroy(&m->error_lock);
    for (size_t i = 0; i < m->n_commands; i++)
        free(m->commands[i]);
    cJSON_Delete(m->health);
    if (m->command_fd >= 0)
        close(m->command_fd);
    free(m->queue);
    free(m);
}
