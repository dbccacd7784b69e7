/* The daemon's configuration: one JSON file, every key listed in a table
 * (src/config/config_keys.c) with its unit, range and default, so that the
 * loader, `uwbd --config-keys` and board/config.md cannot disagree.
 * Unknown keys, wrong types, out-of-range values and missing required keys
 * are errors that name the key: "FILE: key `x.y`: problem". */
#ifndef UWB_CONFIG_CONFIG_LOAD_H
#define UWB_CONFIG_CONFIG_LOAD_H

#include <stdio.h>
#include <stddef.h>

#include "config/config.h"

/* A command-line override: KEY=VALUE, VALUE as JSON (a bare word is taken
 * as a string); KEY may also be a section, replaced by an object. Applied
 * to the file's JSON before validation, so it is checked exactly like the
 * file. */
struct uwbd_override {
    const char *key;
    const char *value;
};

/* Parse config text. `name` prefixes messages. Returns 0, or -1 with err
 * holding "NAME: key `x.y`: problem" (or "NAME: line L column C: ..."). */
int uwbd_config_parse(const char *text, size_t len, const char *name, const struct uwbd_override *overrides,
                      size_t n_overrides, struct uwbd_config *cfg, char *err, size_t errlen);
/* Read and parse a file; an unreadable file is an error too. */
/* What only the running system can say (e.g. that control.group exists):
 * --check-config asks it after loading; "name" prefixes the message. */
int uwbd_config_check_system(const struct uwbd_config *cfg, const char *name, char *err, size_t errlen);

int uwbd_config_load(const char *path, const struct uwbd_override *overrides, size_t n_overrides,
                     struct uwbd_config *cfg, char *err, size_t errlen);

/* Every key as a Markdown table (key, type, unit, default, meaning). */
void uwbd_config_print_keys_markdown(FILE *out);
/* Number of keys in the table and the i-th key's dotted path (for tests). */
size_t uwbd_config_key_count(void);
const char *uwbd_config_key_path(size_t i);

#endif
