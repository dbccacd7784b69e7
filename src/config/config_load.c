/* Loading the daemon's JSON configuration: defaults from the key table,
 * then the file, then command-line overrides, then checks that involve
 * more than one key. Every message names the key. */
#include "config/config_load.h"

#include <cjson/cJSON.h>
#include <grp.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config/config_keys.h"
#include "config/winding_span.h"
#include "util/edit_distance.h"
#include "uwb/migrate.h"
#include "uwb/read_file.h"
#include "uwb/scan.h"

#define PATH_TEXT_MAX 160
/* A config file is a few kilobytes; this bounds what a typo can make us read. */
#define CONFIG_FILE_MAX ((size_t)1024 * 1024)

struct load_context {
    const char *name;
    char *err;
    size_t errlen;
    unsigned char seen[128]; /* per table key: given in the file or an override */
};

static void fail(struct load_context *ctx, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static void fail(struct load_context *ctx, const char *key, const char *fmt, ...)
{
    char problem[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(problem, sizeof problem, fmt, ap);
    va_end(ap);
    if (key)
        snprintf(ctx->err, ctx->errlen, "%s: key `%s`: %s", ctx->name, key, problem);
    else
        snprintf(ctx->err, ctx->errlen, "%s: %s", ctx->name, problem);
}

static const struct config_key *find_key(const char *path, size_t *index)
{
    const struct config_key *k = uwbd_config_key_find(path);
    if (k && index)
        *index = (size_t)(k - uwbd_config_keys);
    return k;
}

/* A section is any proper prefix of a key's path ("gpio", "gpio.lines"). */
static int is_section(const char *path)
{
    size_t n = strlen(path);
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const char *p = uwbd_config_keys[i].path;
        if (strncmp(p, path, n) == 0 && p[n] == '.')
            return 1;
    }
    return 0;
}

/* The key or section at path's depth at most 2 edits from path ("" when
 * none), for "did you mean": `digitiser.sampels` -> `digitiser.samples`. */
static void closest_key(const char *path, char *meant, size_t n)
{
    size_t depth = 0;
    for (const char *dot = strchr(path, '.'); dot; dot = strchr(dot + 1, '.'))
        depth++;
    struct uwb_nearest near;
    uwb_nearest_start(&near, path, strlen(path));
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const char *p = uwbd_config_keys[i].path;
        size_t cut = 0, dots = 0;
        while (p[cut] && !(p[cut] == '.' && dots == depth))
            dots += p[cut++] == '.';
        if (dots >= depth) /* else a shallower key */
            uwb_nearest_offer(&near, p, cut);
    }
    snprintf(meant, n, "%.*s", near.best ? (int)near.best_len : 0, near.best ? near.best : "");
}

/* "unknown key", naming the one meant when one is close. */
static void unknown_key_text(const char *path, char *out, size_t n)
{
    char meant[PATH_TEXT_MAX];
    closest_key(path, meant, sizeof meant);
    if (meant[0])
        snprintf(out, n, "unknown key (did you mean `%s`? uwbd --config-keys lists them all)", meant);
    else
        snprintf(out, n, "unknown key (uwbd --config-keys lists them all)");
}

/* Key names come from the file: quote them printable and short. */
static void printable_name(const char *in, char *out, size_t outlen)
{
    size_t j = 0;
    for (size_t i = 0; in[i] && j + 5 < outlen; i++) {
        unsigned char c = (unsigned char)in[i];
        if (c >= 0x20 && c < 0x7f) {
            out[j++] = (char)c;
        } else {
            j += (size_t)snprintf(out + j, outlen - j, "\\x%02x", c);
        }
        if (i >= 60) {
            snprintf(out + j, outlen - j, "...");
            return;
        }
    }
    out[j] = '\0';
}

static void *field(struct uwbd_config *cfg, const struct config_key *k)
{
    return (char *)cfg + k->offset;
}

static const char *json_type_name(const cJSON *v)
{
    if (cJSON_IsString(v))
        return "a string";
    if (cJSON_IsNumber(v))
        return "a number";
    if (cJSON_IsBool(v))
        return "true/false";
    if (cJSON_IsNull(v))
        return "null";
    if (cJSON_IsArray(v))
        return "an array";
    if (cJSON_IsObject(v))
        return "an object";
    return "something else";
}

static int check_text(struct load_context *ctx, const struct config_key *k, const char *s, size_t size)
{
    size_t n = strlen(s);
    if (n >= size) {
        fail(ctx, k->path, "too long (%zu bytes, at most %zu)", n, size - 1);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        if ((unsigned char)s[i] < 0x20 || s[i] == 0x7f) {
            fail(ctx, k->path, "contains a control character");
            return -1;
        }
    return 0;
}

static void describe_range(const struct config_key *k, char *buf, size_t n)
{
    uwbd_config_key_describe_range(k, buf, n);
}

static int number_in_range(struct load_context *ctx, const struct config_key *k, double v)
{
    char problem[160];
    if (uwbd_config_key_check_range(k, v, problem, sizeof problem) != 0) {
        fail(ctx, k->path, "%s", problem);
        return -1;
    }
    return 0;
}

static int parse_file_mode(struct load_context *ctx, const struct config_key *k, const char *text,
                           struct uwbd_config *cfg)
{
    size_t n = strlen(text);
    if (n < 3 || n > 4 || strspn(text, "01234567") != n) {
        fail(ctx, k->path, "\"%.16s\" is not an octal mode such as \"0660\"", text);
        return -1;
    }
    unsigned mode = (unsigned)strtoul(text, NULL, 8);
    if (mode & 07007) {
        fail(ctx, k->path, "%s gives others access or sets special bits; use e.g. 0660 or 0600", text);
        return -1;
    }
    if ((mode & 0600) != 0600) {
        fail(ctx, k->path, "%s does not let the owner (the daemon) read and write", text);
        return -1;
    }
    cfg->control_mode = mode;
    snprintf(cfg->control_mode_text, sizeof cfg->control_mode_text, "%s", text);
    return 0;
}

static int set_gpio_line(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                         struct uwbd_config *cfg)
{
    size_t line = k->size;
    struct uwb_gpio_config *gpio = field(cfg, k); /* the rig's or the site's */
    if (cJSON_IsNumber(v)) {
        double d = v->valuedouble;
        if (d != floor(d) || d < 0 || d > 1023) {
            fail(ctx, k->path, "%g is not a line offset (an integer 0..1023)", d);
            return -1;
        }
        gpio->offset[line] = (int)d;
        gpio->name[line][0] = '\0';
        return 0;
    }
    if (cJSON_IsString(v)) {
        if (!v->valuestring[0]) {
            fail(ctx, k->path, "empty line name");
            return -1;
        }
        if (check_text(ctx, k, v->valuestring, sizeof gpio->name[line]) != 0)
            return -1;
        gpio->offset[line] = -1;
        snprintf(gpio->name[line], sizeof gpio->name[line], "%s", v->valuestring);
        return 0;
    }
    fail(ctx, k->path, "expected a line offset (integer) or a line name (string), got %s", json_type_name(v));
    return -1;
}

/* One setter per kind of value: each checks the JSON type, then the value,
 * and stores it; -1 after fail() named the key and the problem. */
static int expect_string(struct load_context *ctx, const struct config_key *k, const cJSON *v)
{
    if (cJSON_IsString(v))
        return 0;
    fail(ctx, k->path, "expected a string, got %s", json_type_name(v));
    return -1;
}

static int set_string(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                      struct uwbd_config *cfg)
{
    if (expect_string(ctx, k, v) != 0 || check_text(ctx, k, v->valuestring, k->size) != 0)
        return -1;
    snprintf(field(cfg, k), k->size, "%s", v->valuestring);
    return 0;
}

static int set_choice(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                      struct uwbd_config *cfg)
{
    if (expect_string(ctx, k, v) != 0 || check_text(ctx, k, v->valuestring, k->size) != 0)
        return -1;
    for (const char *const *c = k->choices; *c; c++) {
        if (strcmp(*c, v->valuestring) == 0) {
            snprintf(field(cfg, k), k->size, "%s", v->valuestring);
            return 0;
        }
    }
    char list[128] = "";
    for (const char *const *c = k->choices; *c; c++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", c == k->choices ? "" : ", ", *c);
    fail(ctx, k->path, "\"%.32s\" is not one of %s", v->valuestring, list);
    return -1;
}

static int set_migration(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                         struct uwbd_config *cfg)
{
    if (expect_string(ctx, k, v) != 0)
        return -1;
    if (uwb_migration_kind_parse(v->valuestring, field(cfg, k)) != 0) {
        fail(ctx, k->path, "\"%.32s\" is neither fixed nor float", v->valuestring);
        return -1;
    }
    return 0;
}

static int set_file_mode(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                         struct uwbd_config *cfg)
{
    if (expect_string(ctx, k, v) != 0)
        return -1;
    return parse_file_mode(ctx, k, v->valuestring, cfg);
}

/* KEY_NUMBER (stored times the key's scale) and KEY_INT. */
static int set_number(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                      struct uwbd_config *cfg)
{
    int integer = k->type == KEY_INT;
    if (!cJSON_IsNumber(v)) {
        char range[96];
        describe_range(k, range, sizeof range);
        fail(ctx, k->path, "expected %s in %s, got %s", integer ? "an integer" : "a number", range,
             json_type_name(v));
        return -1;
    }
    if (integer && v->valuedouble != floor(v->valuedouble)) {
        fail(ctx, k->path, "%g is not an integer", v->valuedouble);
        return -1;
    }
    if (number_in_range(ctx, k, v->valuedouble) != 0)
        return -1;
    if (integer)
        *(int *)field(cfg, k) = (int)v->valuedouble;
    else
        *(double *)field(cfg, k) = v->valuedouble * k->scale;
    return 0;
}

static int set_bool(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                    struct uwbd_config *cfg)
{
    if (!cJSON_IsBool(v)) {
        fail(ctx, k->path, "expected true or false, got %s", json_type_name(v));
        return -1;
    }
    *(int *)field(cfg, k) = cJSON_IsTrue(v);
    return 0;
}

/* Two numbers [a, b], each in the key's range; sets the key's flag if it has one. */
static int set_pair(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                    struct uwbd_config *cfg)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2 || !cJSON_IsNumber(cJSON_GetArrayItem(v, 0)) ||
        !cJSON_IsNumber(cJSON_GetArrayItem(v, 1))) {
        fail(ctx, k->path, "expected two numbers [a, b]%s%s", k->unit[0] ? " in " : "", k->unit);
        return -1;
    }
    double *out = field(cfg, k);
    for (int i = 0; i < 2; i++) {
        double d = cJSON_GetArrayItem(v, i)->valuedouble;
        if (number_in_range(ctx, k, d) != 0)
            return -1;
        out[i] = d * k->scale;
    }
    if (k->flag_offset)
        *(int *)((char *)cfg + k->flag_offset) = 1;
    return 0;
}

static int set_value(struct load_context *ctx, const struct config_key *k, const cJSON *v,
                     struct uwbd_config *cfg)
{
    switch (k->type) {
    case KEY_STRING: return set_string(ctx, k, v, cfg);
    case KEY_CHOICE: return set_choice(ctx, k, v, cfg);
    case KEY_MIGRATION: return set_migration(ctx, k, v, cfg);
    case KEY_FILE_MODE: return set_file_mode(ctx, k, v, cfg);
    case KEY_NUMBER:
    case KEY_INT: return set_number(ctx, k, v, cfg);
    case KEY_BOOL: return set_bool(ctx, k, v, cfg);
    case KEY_PAIR: return set_pair(ctx, k, v, cfg);
    case KEY_GPIO_LINE: return set_gpio_line(ctx, k, v, cfg);
    }
    fail(ctx, k->path, "internal error: unknown key type");
    return -1;
}

static int walk_object(struct load_context *ctx, const cJSON *obj, const char *prefix,
                       struct uwbd_config *cfg)
{
    for (const cJSON *item = obj->child; item; item = item->next) {
        const char *name = item->string ? item->string : "";
        char shown[PATH_TEXT_MAX], path[2 * PATH_TEXT_MAX];
        printable_name(name, shown, sizeof shown);
        snprintf(path, sizeof path, "%s%s%s", prefix, prefix[0] ? "." : "", shown);
        for (const cJSON *other = obj->child; other != item; other = other->next)
            if (other->string && strcmp(other->string, name) == 0) {
                fail(ctx, path, "given twice");
                return -1;
            }
        size_t index;
        const struct config_key *k = strcmp(shown, name) == 0 ? find_key(path, &index) : NULL;
        if (k) {
            if (set_value(ctx, k, item, cfg) != 0)
                return -1;
            ctx->seen[index] = 1;
        } else if (strcmp(shown, name) == 0 && is_section(path)) {
            if (!cJSON_IsObject(item)) {
                fail(ctx, path, "expected an object (a section), got %s", json_type_name(item));
                return -1;
            }
            if (walk_object(ctx, item, path, cfg) != 0)
                return -1;
        } else {
            char why[2 * PATH_TEXT_MAX + 64];
            unknown_key_text(path, why, sizeof why);
            fail(ctx, path, "%s", why);
            return -1;
        }
    }
    return 0;
}

static void apply_defaults(struct uwbd_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    /* The rig's own defaults first, for anything this table leaves alone. */
    uwb_rig_config_defaults(&cfg->rig);
    uwb_evaluate_defaults(&cfg->evaluate);
    /* The site's handle opens no line until an integration asks for one. */
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        cfg->site.io.offset[i] = -1;
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        if (k->required)
            continue;
        switch (k->type) {
        case KEY_STRING:
        case KEY_CHOICE:
            snprintf(field(cfg, k), k->size, "%s", k->default_text ? k->default_text : "");
            break;
        case KEY_NUMBER: *(double *)field(cfg, k) = k->default_number * k->scale; break;
        case KEY_INT:
        case KEY_BOOL: *(int *)field(cfg, k) = (int)k->default_number; break;
        case KEY_MIGRATION: uwb_migration_kind_parse(k->default_text, field(cfg, k)); break;
        case KEY_FILE_MODE:
            cfg->control_mode = (unsigned)strtoul(k->default_text, NULL, 8);
            snprintf(cfg->control_mode_text, sizeof cfg->control_mode_text, "%s", k->default_text);
            break;
        case KEY_PAIR:
            if (k->flag_offset)
                *(int *)((char *)cfg + k->flag_offset) = 0;
            break;
        case KEY_GPIO_LINE: break;
        }
    }
}

/* Put an override into the parsed document, creating sections on the way. */
static int apply_override(struct load_context *ctx, cJSON *root, const struct uwbd_override *o)
{
    char shown[PATH_TEXT_MAX];
    printable_name(o->key, shown, sizeof shown);
    if (strcmp(shown, o->key) != 0 || (!find_key(o->key, NULL) && !is_section(o->key))) {
        char why[2 * PATH_TEXT_MAX + 64];
        unknown_key_text(shown, why, sizeof why);
        snprintf(ctx->err, ctx->errlen, "override: key `%s`: %s", shown, why);
        return -1;
    }
    cJSON *value = cJSON_ParseWithOpts(o->value, NULL, 1);
    if (!value)
        value = cJSON_CreateString(o->value);
    if (!value) {
        snprintf(ctx->err, ctx->errlen, "override: key `%s`: out of memory", shown);
        return -1;
    }
    char path[PATH_TEXT_MAX];
    snprintf(path, sizeof path, "%s", o->key);
    cJSON *obj = root;
    char *part = path;
    for (char *dot = strchr(part, '.'); dot; part = dot + 1, dot = strchr(part, '.')) {
        *dot = '\0';
        cJSON *next = cJSON_GetObjectItemCaseSensitive(obj, part);
        const char *problem = NULL;
        if (!next) {
            next = cJSON_AddObjectToObject(obj, part);
            problem = next ? NULL : "out of memory";
        } else if (!cJSON_IsObject(next)) {
            problem = "the file has a value, not a section, on the way";
        }
        if (problem) {
            cJSON_Delete(value);
            snprintf(ctx->err, ctx->errlen, "override: key `%s`: %s", shown, problem);
            return -1;
        }
        obj = next;
    }
    if (cJSON_GetObjectItemCaseSensitive(obj, part))
        cJSON_ReplaceItemInObjectCaseSensitive(obj, part, value);
    else
        cJSON_AddItemToObject(obj, part, value);
    return 0;
}

static int check_endpoint(struct load_context *ctx, const char *key, const char *endpoint)
{
    struct uwb_endpoint ep;
    char why[512];
    if (uwb_endpoint_parse(endpoint, &ep, why, sizeof why) != UWB_LINK_OK) {
        fail(ctx, key, "%s", why);
        return -1;
    }
    return 0;
}

/* Directories state_dir may never be: the root and the Filesystem Hierarchy
 * Standard's top-level and shared directories (FHS 3.0, chapters 3-5), which
 * hold other programs' and users' files. uwbd's start-up cleanup, retention
 * and trims delete inside state_dir, so it must be a directory of its own
 * (e.g. /var/lib/uwbd). */
static const char *const system_directories[] = {
    "/",        "/bin",         "/boot",        "/dev",         "/etc",       "/home",      "/lib",
    "/lib32",   "/lib64",       "/libx32",      "/media",       "/mnt",       "/opt",       "/proc",
    "/root",    "/run",         "/sbin",        "/srv",         "/sys",       "/tmp",       "/usr",
    "/usr/bin", "/usr/include", "/usr/lib",     "/usr/libexec", "/usr/local", "/usr/sbin",  "/usr/share",
    "/usr/src", "/var",         "/var/backups", "/var/cache",   "/var/lib",   "/var/local", "/var/lock",
    "/var/log", "/var/mail",    "/var/opt",     "/var/run",     "/var/spool", "/var/tmp",
};

/* path made lexically canonical: repeated and trailing slashes dropped,
 * "." and ".." resolved; a relative path is left relative. */
static void lexical_path(const char *path, char *out, size_t n)
{
    char buf[UWBD_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    size_t len = 0;
    int absolute = path[0] == '/';
    out[0] = '\0';
    for (char *save = NULL, *part = strtok_r(buf, "/", &save); part; part = strtok_r(NULL, "/", &save)) {
        if (strcmp(part, ".") == 0)
            continue;
        if (strcmp(part, "..") == 0) {
            char *slash = strrchr(out, '/');
            len = slash ? (size_t)(slash - out) : 0;
            out[len] = '\0';
            continue;
        }
        int w = snprintf(out + len, n - len, "%s%s", absolute || len ? "/" : "", part);
        if (w < 0 || (size_t)w >= n - len)
            break;
        len += (size_t)w;
    }
    if (!out[0])
        snprintf(out, n, "%s", absolute ? "/" : ".");
}

/* The system directory `path` names, as given or after resolving symlinks
 * (an existing path only), or NULL. */
static const char *names_system_directory(const char *path)
{
    char lexical[UWBD_PATH_MAX], resolved[PATH_MAX];
    lexical_path(path, lexical, sizeof lexical);
    const char *forms[2] = {lexical, realpath(path, resolved) ? resolved : NULL};
    for (size_t f = 0; f < 2; f++)
        for (size_t i = 0; forms[f] && i < sizeof system_directories / sizeof system_directories[0]; i++)
            if (strcmp(forms[f], system_directories[i]) == 0)
                return system_directories[i];
    return NULL;
}

/* A group a key names must exist here. */
static int check_group(const char *key, const char *group, const char *name, char *err, size_t errlen)
{
    if (!group[0])
        return 0;
    char buf[4096];
    struct group gr, *found = NULL;
    int rc = getgrnam_r(group, &gr, buf, sizeof buf, &found);
    if (rc == 0 && found)
        return 0;
    snprintf(err, errlen, "%s: key `%s`: no group named \"%s\" on this system%s%s", name, key, group,
             rc ? ": " : " (create it, or leave the key empty)", rc ? strerror(rc) : "");
    return -1;
}

int uwbd_config_check_system(const struct uwbd_config *cfg, const char *name, char *err, size_t errlen)
{
    if (check_group("control.group", cfg->control_group, name, err, errlen) != 0)
        return -1;
    return check_group("contacts.test_group", cfg->contacts_test_group, name, err, errlen);
}

/* The GPIO keys each backend needs, and only those. */
static int check_gpio_keys(struct load_context *ctx, const struct uwb_rig_config *r)
{
    int libgpiod = strcmp(r->gpio.backend, "libgpiod") == 0;
    if (libgpiod && !r->gpio.chip[0]) {
        fail(ctx, "gpio.chip", "missing: required with the libgpiod backend");
        return -1;
    }
    if (libgpiod && r->gpio.endpoint[0]) {
        fail(ctx, "gpio.endpoint", "only the emulated backend uses an endpoint (backend is libgpiod)");
        return -1;
    }
    for (size_t i = 0; libgpiod && i < uwbd_config_key_total; i++)
        if (uwbd_config_keys[i].type == KEY_GPIO_LINE &&
            uwbd_config_keys[i].offset == offsetof(struct uwbd_config, rig.gpio) && !ctx->seen[i]) {
            fail(ctx, uwbd_config_keys[i].path, "missing: required with the libgpiod backend (%s)",
                 uwbd_config_keys[i].doc);
            return -1;
        }
    if (!libgpiod && !r->gpio.endpoint[0]) {
        fail(ctx, "gpio.endpoint", "missing: required with the emulated backend");
        return -1;
    }
    if (!libgpiod && check_endpoint(ctx, "gpio.endpoint", r->gpio.endpoint) != 0)
        return -1;
    return 0;
}

/* The other endpoints, the state directory and the control socket. */
static int check_endpoints_and_paths(struct load_context *ctx, const struct uwbd_config *cfg)
{
    const struct uwb_rig_config *r = &cfg->rig;
    if (check_endpoint(ctx, "digitiser.endpoint", r->digitiser.endpoint) != 0)
        return -1;
    if (cfg->console_endpoint[0] && check_endpoint(ctx, "console.endpoint", cfg->console_endpoint) != 0)
        return -1;
    if (cfg->modbus.enabled && !cfg->modbus.endpoint[0]) {
        fail(ctx, "modbus.endpoint",
             "missing: required when modbus.enabled is true (serial:/dev/ttyX, tcp:HOST:PORT)");
        return -1;
    }
    if (cfg->modbus.endpoint[0] && check_endpoint(ctx, "modbus.endpoint", cfg->modbus.endpoint) != 0)
        return -1;
    if (!cfg->state_dir[0]) {
        fail(ctx, "state_dir", "empty");
        return -1;
    }
    const char *system_dir = names_system_directory(cfg->state_dir);
    if (system_dir) {
        fail(ctx, "state_dir",
             "\"%s\" is %s, which holds other files: uwbd deletes inside its state directory, so give it one "
             "of its own (e.g. /var/lib/uwbd)",
             cfg->state_dir, strcmp(system_dir, cfg->state_dir) == 0 ? "a system directory" : system_dir);
        return -1;
    }
    if (!cfg->control_socket[0]) {
        fail(ctx, "control.socket", "empty");
        return -1;
    }
    return 0;
}

/* Checks that involve more than one key, or a key that depends on another. */
static int check_together(struct load_context *ctx, const struct uwbd_config *cfg)
{
    const struct uwb_rig_config *r = &cfg->rig;
    if (check_gpio_keys(ctx, r) != 0 || check_endpoints_and_paths(ctx, cfg) != 0)
        return -1;
    const struct uwb_analysis_options *analysis = &cfg->evaluate.analysis;
    char span_problem[200];
    if (analysis->has_winding_span &&
        uwbd_winding_span_check(analysis->winding_span_m, span_problem, sizeof span_problem) != 0) {
        fail(ctx, UWBD_WINDING_SPAN_KEY, "%s", span_problem);
        return -1;
    }
    if (cfg->evaluate.compare.thresholds.alarm_m < cfg->evaluate.compare.thresholds.watch_m) {
        fail(ctx, "analysis.alarm_mm", "%g mm is below analysis.watch_mm (%g mm)",
             cfg->evaluate.compare.thresholds.alarm_m * 1e3, cfg->evaluate.compare.thresholds.watch_m * 1e3);
        return -1;
    }
    const struct uwb_thresholds *radial = &cfg->evaluate.compare.radial_thresholds;
    if (radial->alarm_m < radial->watch_m) {
        fail(ctx, "radial.alarm_mm", "%g mm is below radial.watch_mm (%g mm)", radial->alarm_m * 1e3,
             radial->watch_m * 1e3);
        return -1;
    }
    /* The rig's rules between fields, where the loader would have met them. */
    const char *rig_key = NULL;
    char rig_why[512];
    if (uwb_rig_config_check_rules(r, &rig_key, rig_why, sizeof rig_why) != UWB_RIG_OK) {
        fail(ctx, rig_key, "%s", rig_why);
        return -1;
    }
    if (!(cfg->evaluate.direct_coupling.window_end_s > r->digitiser.t0_s)) {
        fail(ctx, "direct_coupling.window_end_ns",
             "%g ns is not after the first sample (digitiser.t0_ps = %g ps)",
             cfg->evaluate.direct_coupling.window_end_s * 1e9, r->digitiser.t0_s * 1e12);
        return -1;
    }
    const char *site_key = NULL;
    char site_why[512];
    if (uwbd_site_config_check(cfg, &site_key, site_why, sizeof site_why) != 0) {
        fail(ctx, site_key, "%s", site_why);
        return -1;
    }
    /* The rig's own checks, for anything the table cannot express. */
    char why[512];
    if (uwb_rig_config_check(r, why, sizeof why) != UWB_RIG_OK) {
        fail(ctx, NULL, "%s", why);
        return -1;
    }
    return 0;
}

/* "line L column C" of a byte offset, for JSON syntax errors. */
static void locate(const char *text, size_t offset, int *line, int *column)
{
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n') {
            ++*line;
            *column = 1;
        } else {
            ++*column;
        }
    }
}

int uwbd_config_parse(const char *text, size_t len, const char *name, const struct uwbd_override *overrides,
                      size_t n_overrides, struct uwbd_config *cfg, char *err, size_t errlen)
{
    struct load_context ctx = {.name = name ? name : "(config)", .err = err, .errlen = errlen};
    apply_defaults(cfg);
    if (uwbd_config_key_total > sizeof ctx.seen) {
        fail(&ctx, NULL, "internal error: the key table outgrew the loader");
        return -1;
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!root) {
        int line, column;
        size_t at = end && end >= text && end <= text + len ? (size_t)(end - text) : 0;
        locate(text, at, &line, &column);
        fail(&ctx, NULL, "line %d column %d: not valid JSON", line, column);
        return -1;
    }
    size_t used = (size_t)(end - text);
    while (used < len && text[used] && strchr(" \t\r\n", text[used]))
        used++;
    int rc = -1;
    if (used < len) {
        int line, column;
        locate(text, used, &line, &column);
        fail(&ctx, NULL, "line %d column %d: text after the end of the JSON object", line, column);
    } else if (!cJSON_IsObject(root)) {
        fail(&ctx, NULL, "the configuration must be one JSON object, got %s", json_type_name(root));
    } else {
        rc = 0;
        for (size_t i = 0; rc == 0 && i < n_overrides; i++)
            rc = apply_override(&ctx, root, &overrides[i]);
        if (rc == 0)
            rc = walk_object(&ctx, root, "", cfg);
    }
    cJSON_Delete(root);
    if (rc != 0)
        return -1;
    for (size_t i = 0; i < uwbd_config_key_total; i++)
        if (uwbd_config_keys[i].required && !ctx.seen[i]) {
            fail(&ctx, uwbd_config_keys[i].path, "missing (required: %s)", uwbd_config_keys[i].doc);
            return -1;
        }
    if (check_together(&ctx, cfg) != 0)
        return -1;
    uwbd_site_config_finish(cfg);
    return 0;
}

int uwbd_config_load(const char *path, const struct uwbd_override *overrides, size_t n_overrides,
                     struct uwbd_config *cfg, char *err, size_t errlen)
{
    char *text;
    size_t len;
    enum uwb_read_result read_result = uwb_read_file(path, CONFIG_FILE_MAX, &text, &len, err, errlen);
    if (read_result == UWB_READ_TOO_BIG) {
        size_t used = strlen(err);
        snprintf(err + used, errlen - used, ": not a configuration file");
    }
    if (read_result != UWB_READ_OK)
        return -1;
    int rc = uwbd_config_parse(text, len, path, overrides, n_overrides, cfg, err, errlen);
    free(text);
    return rc;
}

static void print_default(FILE *out, const struct config_key *k)
{
    if (k->required) {
        fputs("required", out);
        return;
    }
    switch (k->type) {
    case KEY_STRING:
    case KEY_CHOICE:
    case KEY_MIGRATION:
    case KEY_FILE_MODE: fprintf(out, "`\"%s\"`", k->default_text ? k->default_text : ""); break;
    case KEY_BOOL: fputs(k->default_number != 0 ? "`true`" : "`false`", out); break;
    case KEY_NUMBER:
    case KEY_INT: fprintf(out, "`%g`", k->default_number); break;
    case KEY_PAIR: fputs("absent", out); break;
    case KEY_GPIO_LINE: fputs(k->default_text ? k->default_text : "required with libgpiod", out); break;
    }
}

static const char *type_text(const struct config_key *k)
{
    switch (k->type) {
    case KEY_STRING: return "string";
    case KEY_NUMBER: return "number";
    case KEY_INT: return "integer";
    case KEY_BOOL: return "boolean";
    case KEY_PAIR: return "[number, number]";
    case KEY_GPIO_LINE: return "integer or string";
    // NOLINTNEXTLINE(bugprone-branch-clone): two key types that both read as a string
    case KEY_CHOICE: return "string";
    case KEY_MIGRATION: return "string";
    case KEY_FILE_MODE: return "octal string";
    }
    return "?";
}

void uwbd_config_print_keys_markdown(FILE *out)
{
    fputs("| key | type | unit | range | default | meaning |\n|---|---|---|---|---|---|\n", out);
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        fprintf(out, "| `%s` | %s | %s | ", k->path, type_text(k), k->unit[0] ? k->unit : "");
        if (k->type == KEY_NUMBER || k->type == KEY_INT || k->type == KEY_PAIR) {
            char range[96];
            describe_range(k, range, sizeof range);
            /* The unit has its own column. */
            char *space = strrchr(range, ']');
            if (space)
                space[1] = '\0';
            fputs(range, out);
        } else if (k->type == KEY_CHOICE) {
            for (const char *const *c = k->choices; *c; c++)
                fprintf(out, "%s`%s`", c == k->choices ? "" : ", ", *c);
        } else if (k->type == KEY_MIGRATION) {
            fputs("`fixed`, `float`", out);
        }
        fputs(" | ", out);
        print_default(out, k);
        fprintf(out, " | %s |\n", k->doc);
    }
}

size_t uwbd_config_key_count(void)
{
    return uwbd_config_key_total;
}

const char *uwbd_config_key_path(size_t i)
{
    return i < uwbd_config_key_total ? uwbd_config_keys[i].path : NULL;
}
