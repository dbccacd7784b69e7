/* The alarm contacts' latch across restarts: contacts-latch.json in the
 * state directory, written atomically whenever what it holds changes, read
 * once at start (board/state-dir.md). */
#ifndef UWB_STATE_CONTACTS_LATCH_H
#define UWB_STATE_CONTACTS_LATCH_H

#include <stddef.h>

#include "state/store.h"
#include "integrations/alarm_contacts.h"

#define UWBD_CONTACTS_LATCH_FILE "contacts-latch.json"

/* The latch file's path in the store. Returns 0, or -1 if it does not fit. */
int uwbd_contacts_latch_path(const struct uwbd_store *store, char *out, size_t n);

/* UWBD_CONTACTS_KEPT with *out filled; UWBD_CONTACTS_KEPT_NONE when there
 * is no such file; UWBD_CONTACTS_KEPT_UNREADABLE with `why` ("PATH:
 * problem") when it cannot be read or is not what uwbd writes. */
enum uwbd_contacts_kept uwbd_contacts_latch_read(const char *path, struct uwbd_contacts_memory *out,
                                                 char *why, size_t whylen);

/* Replaces the file atomically. Returns 0, or -1 with err; the file is then
 * the one before. */
int uwbd_contacts_latch_write(const char *path, const struct uwbd_contacts_memory *memory, char *err,
                              size_t errlen);

#endif
