/* The site's configuration checks: an integration that is on must have
 * what it needs (its lines or endpoint, the asset id), named by key, so
 * that `uwbd --check-config` refuses it before anything opens. */
#include "config/site_config.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config/config.h"
#include "uwb/link.h"

int uwbd_site_any_enabled(const struct uwbd_config *cfg)
{
    return cfg->site.contacts_enabled || cfg->site.event_enabled || cfg->site.prometheus_enabled ||
           cfg->site.mqtt_enabled;
}

static int line_configured(const struct uwb_gpio_config *io, int line)
{
    return io->offset[line] >= 0 || io->name[line][0];
}

static int check_asset_id(const char *id, char *why, size_t whylen)
{
    size_t n = strlen(id);
    if (n != strspn(id, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-")) {
        snprintf(why, whylen,
                 "\"%s\": only letters, digits, '.', '_' and '-' (it names MQTT topics and metrics)", id);
        return -1;
    }
    if (n > 0 && (id[0] == '.' || id[0] == '-')) {
        snprintf(why, whylen, "\"%s\" must start with a letter, a digit or '_'", id);
        return -1;
    }
    return 0;
}

/* The lines an enabled integration needs, and the site endpoint on the emulated board. */
static int check_lines(const struct uwbd_config *cfg, int enabled, const int *lines, const char *const *keys,
                       int count, const char *what, const char **key, char *why, size_t whylen)
{
    if (!enabled)
        return 0;
    const struct uwbd_site_config *s = &cfg->site;
    if (strcmp(cfg->rig.gpio.backend, "libgpiod") == 0) {
        for (int i = 0; i < count; i++)
            if (!line_configured(&s->io, lines[i])) {
                *key = keys[i];
                snprintf(why, whylen, "missing: required with the libgpiod backend when %s is true", what);
                return -1;
            }
        return 0;
    }
    if (!s->io.endpoint[0]) {
        *key = "gpio.site_endpoint";
        snprintf(why, whylen,
                 "missing: the emulated board's site lines are needed when %s is true "
                 "(uwbemu --site-io ENDPOINT)",
                 what);
        return -1;
    }
    struct uwb_endpoint ep;
    char inner[256];
    if (uwb_endpoint_parse(s->io.endpoint, &ep, inner, sizeof inner) != UWB_LINK_OK) {
        *key = "gpio.site_endpoint";
        snprintf(why, whylen, "%s", inner);
        return -1;
    }
    if (strcmp(s->io.endpoint, cfg->rig.gpio.endpoint) == 0) {
        *key = "gpio.site_endpoint";
        snprintf(why, whylen, "\"%s\" is gpio.endpoint too: the site's lines have an endpoint of their own",
                 s->io.endpoint);
        return -1;
    }
    return 0;
}

/* node_exporter's textfile collector reads *.prom files only. */
static int check_textfile(const struct uwbd_site_config *s, const char **key, char *why, size_t whylen)
{
    if (!s->prometheus_enabled)
        return 0;
    *key = "prometheus.textfile";
    size_t n = strlen(s->prometheus_textfile);
    if (n == 0) {
        snprintf(why, whylen,
                 "missing: required when prometheus.enabled is true (e.g. "
                 "/var/lib/prometheus/node-exporter/uwbd.prom)");
        return -1;
    }
    const char *slash = strrchr(s->prometheus_textfile, '/');
    const char *name = slash ? slash + 1 : s->prometheus_textfile;
    if (strlen(name) <= 5 || strcmp(s->prometheus_textfile + n - 5, ".prom") != 0) {
        snprintf(why, whylen,
                 "\"%s\": the name must end in .prom (node_exporter's textfile collector reads "
                 "no other)",
                 s->prometheus_textfile);
        return -1;
    }
    return 0;
}

/* A file the daemon reads at start (a CA, a certificate, a key, the
 * password): it must be there, be a regular file and be readable by this
 * user, or libmosquitto refuses it later without naming it. The open does
 * not block (a FIFO) nor follow a final symlink out of reach unseen: fstat
 * says what it is. */
static int check_readable_file(const char *path, const char *name, const char **key, char *why, size_t whylen,
                               struct stat *st)
{
    *key = name;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        snprintf(why, whylen, "\"%s\": %s", path, strerror(errno));
        return -1;
    }
    int rc = fstat(fd, st);
    int saved = errno;
    close(fd);
    if (rc != 0) {
        snprintf(why, whylen, "\"%s\": %s", path, strerror(saved));
        return -1;
    }
    if (!S_ISREG(st->st_mode)) {
        snprintf(why, whylen, "\"%s\" is not a regular file", path);
        return -1;
    }
    return 0;
}

/* A file only the service may read: the broker's password, a TLS key. */
static int check_secret_file(const char *path, const char *name, const char **key, char *why, size_t whylen)
{
    struct stat st;
    if (check_readable_file(path, name, key, why, whylen, &st) != 0)
        return -1;
    if (st.st_mode & 077) {
        snprintf(why, whylen,
                 "\"%s\" is readable by others (mode %04o): make it the service's only "
                 "(chmod 0600)",
                 path, (unsigned)(st.st_mode & 07777));
        return -1;
    }
    return 0;
}

static int check_mqtt(const struct uwbd_site_config *s, const char **key, char *why, size_t whylen)
{
    if (!s->mqtt_enabled)
        return 0;
    *key = "mqtt.endpoint";
    if (!s->mqtt_endpoint[0]) {
        snprintf(why, whylen, "missing: required when mqtt.enabled is true (tcp:HOST:PORT of the broker)");
        return -1;
    }
    struct uwb_endpoint ep;
    char inner[256];
    if (uwb_endpoint_parse(s->mqtt_endpoint, &ep, inner, sizeof inner) != UWB_LINK_OK ||
        ep.kind != UWB_ENDPOINT_TCP) {
        snprintf(why, whylen, "\"%s\": the broker is tcp:HOST:PORT", s->mqtt_endpoint);
        return -1;
    }
    if (s->mqtt_username[0] && !s->mqtt_password_file[0]) {
        *key = "mqtt.password_file";
        snprintf(why, whylen, "missing: required with mqtt.username (a file readable by the service only)");
        return -1;
    }
    if (s->mqtt_password_file[0] && !s->mqtt_username[0]) {
        *key = "mqtt.username";
        snprintf(why, whylen, "missing: mqtt.password_file is set, for which user?");
        return -1;
    }
    if (s->mqtt_password_file[0] &&
        check_secret_file(s->mqtt_password_file, "mqtt.password_file", key, why, whylen))
        return -1;
    if (!s->mqtt_cert_file[0] != !s->mqtt_key_file[0]) {
        *key = s->mqtt_cert_file[0] ? "mqtt.key_file" : "mqtt.cert_file";
        snprintf(why, whylen, "missing: a client certificate needs both mqtt.cert_file and mqtt.key_file");
        return -1;
    }
    if (s->mqtt_cert_file[0] && !s->mqtt_ca_file[0]) {
        *key = "mqtt.ca_file";
        snprintf(why, whylen, "missing: a client certificate is for TLS, which mqtt.ca_file turns on");
        return -1;
    }
    struct stat st;
    if (s->mqtt_ca_file[0] && check_readable_file(s->mqtt_ca_file, "mqtt.ca_file", key, why, whylen, &st))
        return -1;
    if (s->mqtt_cert_file[0] &&
        check_readable_file(s->mqtt_cert_file, "mqtt.cert_file", key, why, whylen, &st))
        return -1;
    if (s->mqtt_key_file[0] && check_secret_file(s->mqtt_key_file, "mqtt.key_file", key, why, whylen))
        return -1;
    const char *prefix = s->mqtt_topic_prefix;
    *key = "mqtt.topic_prefix";
    if (!prefix[0] || strpbrk(prefix, "+#") || prefix[0] == '/' || prefix[strlen(prefix) - 1] == '/') {
        snprintf(why, whylen, "\"%s\": a topic without wildcards (+ #) nor a leading or trailing /", prefix);
        return -1;
    }
    return 0;
}

int uwbd_site_config_check(const struct uwbd_config *cfg, const char **key, char *why, size_t whylen)
{
    const struct uwbd_site_config *s = &cfg->site;
    *key = NULL;
    why[0] = '\0';
    if (check_asset_id(s->asset_id, why, whylen) != 0) {
        *key = "site.asset_id";
        return -1;
    }
    if (uwbd_site_any_enabled(cfg) && !s->asset_id[0]) {
        *key = "site.asset_id";
        snprintf(why, whylen, "missing: required once an integration is on (%s)",
                 s->contacts_enabled     ? "contacts.enabled"
                 : s->event_enabled      ? "event.enabled"
                 : s->prometheus_enabled ? "prometheus.enabled"
                                         : "mqtt.enabled");
        return -1;
    }
    static const int contact_lines[] = {UWB_LINE_WATCH, UWB_LINE_ALARM, UWB_LINE_FAULT};
    static const char *const contact_keys[] = {"contacts.watch.line", "contacts.alarm.line",
                                               "contacts.fault.line"};
    if (check_lines(cfg, s->contacts_enabled, contact_lines, contact_keys, 3, "contacts.enabled", key, why,
                    whylen) != 0)
        return -1;
    static const int event_lines[] = {UWB_LINE_EVENT};
    static const char *const event_keys[] = {"event.line"};
    if (check_lines(cfg, s->event_enabled, event_lines, event_keys, 1, "event.enabled", key, why, whylen) !=
        0)
        return -1;
    if (s->event_enabled && s->event_debounce_s > 0 && s->event_poll_s > s->event_debounce_s) {
        *key = "event.poll_ms";
        snprintf(why, whylen, "%g ms is above event.debounce_ms (%g ms): a bounce would go unseen",
                 s->event_poll_s * 1e3, s->event_debounce_s * 1e3);
        return -1;
    }
    if (check_textfile(s, key, why, whylen) != 0)
        return -1;
    if (check_mqtt(s, key, why, whylen) != 0)
        return -1;
    if (!s->io.endpoint[0] || strcmp(cfg->rig.gpio.backend, "emulated") == 0)
        return 0;
    *key = "gpio.site_endpoint";
    snprintf(why, whylen, "only the emulated backend uses an endpoint (backend is %s)",
             cfg->rig.gpio.backend);
    return -1;
}

void uwbd_site_config_finish(struct uwbd_config *cfg)
{
    struct uwb_gpio_config *io = &cfg->site.io;
    snprintf(io->backend, sizeof io->backend, "%s", cfg->rig.gpio.backend);
    snprintf(io->chip, sizeof io->chip, "%s", cfg->rig.gpio.chip);
    io->lines = 0;
    if (cfg->site.contacts_enabled)
        io->lines |= UWB_GPIO_LINE_BIT(UWB_LINE_WATCH) | UWB_GPIO_LINE_BIT(UWB_LINE_ALARM) |
                     UWB_GPIO_LINE_BIT(UWB_LINE_FAULT);
    if (cfg->site.event_enabled)
        io->lines |= UWB_GPIO_LINE_BIT(UWB_LINE_EVENT);
}
