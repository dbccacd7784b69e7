/* The table of configuration keys shared by the loader and the key listing. */
#ifndef UWB_DAEMON_CONFIG_KEYS_H
#define UWB_DAEMON_CONFIG_KEYS_H

#include <stddef.h>

enum config_key_type {
    KEY_STRING,      /* char[size] */
    KEY_NUMBER,      /* double, stored = written * scale */
    KEY_INT,         /* int */
    KEY_BOOL,        /* int 0/1 */
    KEY_PAIR,        /* double[2], stored = written * scale; optional ones set a flag */
    KEY_GPIO_LINE,   /* an offset (integer) or a line name (string) */
    KEY_CHOICE,      /* char[size], one of choices */
    KEY_MIGRATION,   /* enum uwb_migration_kind from "fixed" / "float" */
    KEY_FILE_MODE,   /* octal string, e.g. "0660" */
};

struct config_key {
    const char *path;          /* dotted, e.g. "digitiser.samples" */
    enum config_key_type type;
    size_t offset;             /* into struct uwbd_config */
    size_t size;               /* string buffer size; the GPIO line index for KEY_GPIO_LINE */
    size_t flag_offset;        /* KEY_PAIR without default: int set to 1 when given; 0 = none */
    double scale;              /* written unit -> stored unit */
    double min, max;           /* allowed range in written units */
    int min_exclusive;         /* value must be > min rather than >= */
    int required;
    double default_number;     /* when not required (numbers, ints, bools) */
    const char *default_text;  /* when not required (strings, choices, modes) */
    const char *unit;          /* written unit, "" for none */
    const char *const *choices;/* KEY_CHOICE: NULL-terminated */
    const char *doc;
};

extern const struct config_key uwbd_config_keys[];
extern const size_t uwbd_config_key_total;

#endif
