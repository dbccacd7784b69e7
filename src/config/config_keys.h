/* The table of configuration keys shared by the loader and the key listing. */
#ifndef UWB_CONFIG_CONFIG_KEYS_H
#define UWB_CONFIG_CONFIG_KEYS_H

#include <stddef.h>

enum config_key_type {
    KEY_STRING,    /* char[size] */
    KEY_NUMBER,    /* double, stored = written * scale */
    KEY_INT,       /* int */
    KEY_BOOL,      /* int 0/1 */
    KEY_PAIR,      /* double[2], stored = written * scale; optional ones set a flag */
    KEY_GPIO_LINE, /* an offset (integer) or a line name (string) */
    KEY_CHOICE,    /* char[size], one of choices */
    KEY_MIGRATION, /* enum uwb_migration_kind from "fixed" / "float" */
    KEY_FILE_MODE, /* octal string, e.g. "0660" */
};

struct config_key {
    const char *path; /* dotted, e.g. "digitiser.samples" */
    enum config_key_type type;
    size_t offset;             /* into struct uwbd_config */
    size_t size;               /* string buffer size; the GPIO line index for KEY_GPIO_LINE */
    size_t flag_offset;        /* KEY_PAIR without default: int set to 1 when given; 0 = none */
    double scale;              /* written unit -> stored unit */
    double min, max;           /* allowed range in written units */
    int min_exclusive;         /* value must be > min rather than >= */
    const char *below_min_why; /* said after "out of range" when a value is under min; NULL: nothing */
    int required;
    double default_number;      /* when not required (numbers, ints, bools) */
    const char *default_text;   /* when not required (strings, choices, modes) */
    const char *unit;           /* written unit, "" for none */
    const char *const *choices; /* KEY_CHOICE: NULL-terminated */
    const char *doc;
};

extern const struct config_key uwbd_config_keys[];
extern const size_t uwbd_config_key_total;

/* The key at dotted `path`, or NULL. */
const struct config_key *uwbd_config_key_find(const char *path);
/* 0 when `written` (in the key's unit) lies in its range; else -1 with
 * problem = "V is out of range [lo, hi] unit". The loader and the rig's
 * checks both judge a value by this, so they cannot disagree. */
int uwbd_config_key_check_range(const struct config_key *k, double written, char *problem, size_t n);
/* "[lo, hi] unit" or "(lo, hi] unit", as the messages and the key listing write it. */
void uwbd_config_key_describe_range(const struct config_key *k, char *buf, size_t n);
/* 1 when the key lands in struct uwb_rig_config (gpio, digitiser, carriage,
 * scan, geometry), with *offset its place there and *flag_offset that of
 * its "given" flag (0: none); 0 for the daemon's own keys. These rows
 * take their ranges and defaults from the rig's specs (src/rig/rig_keys.h). */
int uwbd_config_key_in_rig(const struct config_key *k, size_t *offset, size_t *flag_offset);

#endif
