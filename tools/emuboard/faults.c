/* Fault knobs: off, on (every time), every Nth time, or the next N times. */
#include <stdio.h>
#include <string.h>

#include "emu.h"

static const char *const names[EMU_FAULT_COUNT] = {
    "crc", "truncate", "drop", "silent", "disconnect", "home-never", "home-stuck", "lose-steps",
};

const char *emu_fault_name(enum emu_fault_id id)
{
    return (int)id >= 0 && id < EMU_FAULT_COUNT ? names[id] : "?";
}

int emu_fault_find(const char *name)
{
    for (int i = 0; i < EMU_FAULT_COUNT; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

int emu_fault_active(const struct emu_fault *f)
{
    return f->mode != EMU_FAULT_OFF;
}

int emu_fault_strikes(struct emu_fault *f)
{
    int strikes = 0;
    switch (f->mode) {
    case EMU_FAULT_OFF: break;
    case EMU_FAULT_ON: strikes = 1; break;
    case EMU_FAULT_EVERY: strikes = ++f->seen % f->n == 0; break;
    case EMU_FAULT_NEXT:
        strikes = f->n > 0;
        if (strikes && --f->n == 0)
            f->mode = EMU_FAULT_OFF;
        break;
    }
    f->hits += (unsigned long)strikes;
    return strikes;
}

void emu_fault_describe(const struct emu_fault *f, char *buf, size_t buflen)
{
    switch (f->mode) {
    case EMU_FAULT_OFF: snprintf(buf, buflen, "off"); break;
    case EMU_FAULT_ON: snprintf(buf, buflen, "on"); break;
    case EMU_FAULT_EVERY: snprintf(buf, buflen, "every %u", f->n); break;
    case EMU_FAULT_NEXT: snprintf(buf, buflen, "next %u", f->n); break;
    }
}
