/* MQTT publishing through libmosquitto's own network thread (see the
 * header). The queue is shared with that thread's callbacks: one mutex
 * guards it; the callbacks only publish and unlink, never block. */
#include "integrations/mqtt_publisher.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/eventfd.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "uwb/atomic_file.h"
#include "daemon/log.h"
#include "integrations/mosquitto_loader.h"
#include "uwb/link.h"
#include "uwb/read_file.h"

#define KEEPALIVE_S 60
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
    char cmd_topic[256], reply_topic[256];
    char health_topic[256];
    char *health;                 /* the latest health report, sent on every connection */
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

static void on_connect(struct mosquitto *mosq, void *ctx, int rc)
{
    struct uwbd_mqtt *m = ctx;
    if (rc != 0) {
        uwbd_log(UWBD_LOG_WARNING, "mqtt: the broker refused the connection: %s", m->lib->connack_string(rc));
        return;
    }
    pthread_mutex_lock(&m->lock);
    m->connected = 1;
    m->was_connected = 1;
    m->inflight_mid = 0; /* a publish cut off by the disconnection is sent again: at least once */
    m->lib->publish(mosq, NULL, m->status_topic, 6, "online", QOS, true);
    if (m->command_fd >= 0)
        m->lib->subscribe(mosq, NULL, m->cmd_topic, QOS);
    if (m->health)
        m->lib->publish(mosq, NULL, m->health_topic, (int)strlen(m->health), m->health, QOS, true);
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

static int configure(struct uwbd_mqtt *m, const struct uwbd_site_config *cfg, char *err, size_t errlen)
{
    m->lib->connect_callback_set(m->mosq, on_connect);
    m->lib->disconnect_callback_set(m->mosq, on_disconnect);
    m->lib->publish_callback_set(m->mosq, on_publish);
    m->lib->message_callback_set(m->mosq, on_message);
    int rc = m->lib->will_set(m->mosq, m->status_topic, 7, "offline", QOS, true);
    if (rc == MOSQ_ERR_SUCCESS && cfg->mqtt_username[0]) {
        char password[512];
        if (read_password(cfg->mqtt_password_file, password, sizeof password, err, errlen) != 0)
            return -1;
        rc = m->lib->username_pw_set(m->mosq, cfg->mqtt_username, password);
        memset(password, 0, sizeof password);
    }
    if (rc == MOSQ_ERR_SUCCESS && cfg->mqtt_ca_file[0])
        rc = m->lib->tls_set(m->mosq, cfg->mqtt_ca_file, NULL,
                             cfg->mqtt_cert_file[0] ? cfg->mqtt_cert_file : NULL,
                             cfg->mqtt_key_file[0] ? cfg->mqtt_key_file : NULL, NULL);
    if (rc == MOSQ_ERR_SUCCESS)
        rc = m->lib->reconnect_delay_set(m->mosq, 1, (unsigned)(cfg->mqtt_reconnect_max_s + 0.5), true);
    if (rc != MOSQ_ERR_SUCCESS) {
        snprintf(err, errlen, "mqtt: %s", m->lib->strerror(rc));
        return -1;
    }
    return 0;
}

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
    pthread_mutex_init(&m->lock, NULL);
    snprintf(m->dir, sizeof m->dir, "%s/" QUEUE_DIR, state_dir);
    snprintf(m->verdict_topic, sizeof m->verdict_topic, "%s/%s/verdict", cfg->mqtt_topic_prefix,
             cfg->asset_id);
    snprintf(m->status_topic, sizeof m->status_topic, "%s/%s/status", cfg->mqtt_topic_prefix, cfg->asset_id);
    m->queue_max = cfg->mqtt_queue_max;
    snprintf(m->cmd_topic, sizeof m->cmd_topic, "%s/%s/cmd", cfg->mqtt_topic_prefix, cfg->asset_id);
    snprintf(m->reply_topic, sizeof m->reply_topic, "%s/%s/reply", cfg->mqtt_topic_prefix, cfg->asset_id);
    snprintf(m->health_topic, sizeof m->health_topic, "%s/%s/health", cfg->mqtt_topic_prefix, cfg->asset_id);
    m->command_fd = cfg->mqtt_commands ? eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK) : -1;
    if (cfg->mqtt_commands && m->command_fd < 0) {
        snprintf(err, errlen, "mqtt: eventfd: %s", strerror(errno));
        pthread_mutex_destroy(&m->lock);
        free(m);
        return -1;
    }
    m->lib->lib_init();
    char client_id[128];
    snprintf(client_id, sizeof client_id, "uwbd-%s", cfg->asset_id);
    m->mosq = m->lib->new (client_id, true, m);
    if (!m->mosq || load_queue(m, err, errlen) != 0 || configure(m, cfg, err, errlen) != 0) {
        if (!m->mosq)
            snprintf(err, errlen, "mqtt: out of memory");
        uwbd_mqtt_close(m);
        return -1;
    }
    int rc = m->lib->connect_async(m->mosq, ep.host, (int)strtol(ep.port, NULL, 10), KEEPALIVE_S);
    if (rc != MOSQ_ERR_SUCCESS)
        uwbd_log(UWBD_LOG_WARNING, "mqtt: %s: %s; trying again in the background", cfg->mqtt_endpoint,
                 rc == MOSQ_ERR_ERRNO ? strerror(errno) : m->lib->strerror(rc));
    rc = m->lib->loop_start(m->mosq);
    if (rc != MOSQ_ERR_SUCCESS) {
        snprintf(err, errlen, "mqtt: cannot start its thread: %s", m->lib->strerror(rc));
        uwbd_mqtt_close(m);
        return -1;
    }
    uwbd_log(UWBD_LOG_INFO, "mqtt: publishing to %s on %s (%zu verdict(s) queued from before)",
             m->verdict_topic, cfg->mqtt_endpoint, m->queued);
    *out = m;
    return 0;
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
    char *copy = strdup(health_json);
    pthread_mutex_lock(&m->lock);
    if (copy) {
        free(m->health);
        m->health = copy;
    }
    if (m->connected && m->health)
        m->lib->publish(m->mosq, NULL, m->health_topic, (int)strlen(m->health), m->health, QOS, true);
    pthread_mutex_unlock(&m->lock);
}

size_t uwbd_mqtt_queued(struct uwbd_mqtt *m)
{
    pthread_mutex_lock(&m->lock);
    size_t n = m->queued;
    pthread_mutex_unlock(&m->lock);
    return n;
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
        m->lib->disconnect(m->mosq);
        m->lib->loop_stop(m->mosq, true);
        m->lib->destroy(m->mosq);
    }
    m->lib->lib_cleanup();
    pthread_mutex_destroy(&m->lock);
    for (size_t i = 0; i < m->n_commands; i++)
        free(m->commands[i]);
    free(m->health);
    if (m->command_fd >= 0)
        close(m->command_fd);
    free(m->queue);
    free(m);
}
