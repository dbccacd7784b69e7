/* The disks' radial changes: the text of radial_m ("I-J:METRES,..."), each
 * disk's front offset from it and face_tilt_m, and rewriting it when one
 * range of disks changes (uwbemu's `set radial`). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

/* A front moved this far (m) is not a radial change but a typo. */
#define RADIAL_LIMIT_M 1.0

struct radial_entry {
    int from, to; /* 1-based, from <= to */
    double metres;
};

static const char *skip_space(const char *p)
{
    while (isspace((unsigned char)*p))
        p++;
    return p;
}

static int parse_disk(const char **p, int *disk)
{
    if (!isdigit((unsigned char)**p))
        return -1;
    char *end;
    errno = 0;
    long v = strtol(*p, &end, 10);
    if (errno || v < 1 || v > SIM_DISKS_MAX)
        return -1;
    *disk = (int)v;
    *p = end;
    return 0;
}

/* Calls `each` for every entry of text in order; -1 with err on bad syntax. */
static int parse_entries(const char *text, int (*each)(const struct radial_entry *, void *), void *ctx,
                         char *err, size_t errlen)
{
    const char *p = skip_space(text);
    while (*p) {
        const char *start = p;
        struct radial_entry e = {0, 0, 0.0};
        int ok = parse_disk(&p, &e.from) == 0;
        e.to = e.from;
        if (ok && *p == '-') {
            p++;
            ok = parse_disk(&p, &e.to) == 0 && e.to >= e.from;
        }
        ok = ok && *p == ':';
        if (ok) {
            p++;
            char *end;
            errno = 0;
            e.metres = strtod(p, &end);
            ok = end != p && errno == 0 && isfinite(e.metres) && fabs(e.metres) <= RADIAL_LIMIT_M;
            p = end;
        }
        p = skip_space(p);
        if (!ok || (*p && *p != ',')) {
            size_t n = strcspn(start, ",");
            if (n == 0) {
                snprintf(err, errlen, "radial_m: an empty entry in \"%.60s\"", text);
                return -1;
            }
            snprintf(err, errlen,
                     "radial_m: \"%.*s\" is not FROM-TO:METRES or DISK:METRES (disks 1..%d from the bottom, "
                     "FROM <= TO, |METRES| <= %g)",
                     (int)(n > 60 ? 60 : n), start, SIM_DISKS_MAX, RADIAL_LIMIT_M);
            return -1;
        }
        if (each && each(&e, ctx) != 0) {
            snprintf(err, errlen, "radial_m: disks %d-%d: the winding has fewer disks", e.from, e.to);
            return -1;
        }
        if (*p == ',')
            p = skip_space(p + 1);
    }
    return 0;
}

int sim_radial_check(const char *value, char *err, size_t errlen)
{
    return parse_entries(value, NULL, NULL, err, errlen);
}

struct fronts {
    double *front;
    int disks;
};

static int assign(const struct radial_entry *e, void *ctx)
{
    struct fronts *f = ctx;
    if (e->to > f->disks)
        return -1;
    for (int i = e->from; i <= e->to; i++)
        f->front[i - 1] = e->metres;
    return 0;
}

int sim_scene_radial_changes(const struct sim_scene *s, double *front, char *err, size_t errlen)
{
    for (int i = 0; i < s->disks; i++)
        front[i] = 0.0;
    struct fronts f = {front, s->disks};
    return parse_entries(s->radial_m, assign, &f, err, errlen);
}

int sim_scene_disk_fronts(const struct sim_scene *s, double *front, char *err, size_t errlen)
{
    if (sim_scene_radial_changes(s, front, err, errlen) != 0)
        return -1;
    if (s->face_tilt_m != 0 && s->disks > 1)
        for (int i = 0; i < s->disks; i++)
            front[i] += s->face_tilt_m * i / (s->disks - 1);
    return 0;
}

/* The shortest text that reads back as exactly v. */
static void format_metres(char *buf, size_t buflen, double v)
{
    for (int digits = 1; digits <= 17; digits++) {
        snprintf(buf, buflen, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            return;
    }
}

int sim_scene_set_radial(struct sim_scene *s, int from, int to, double metres, char *err, size_t errlen)
{
    double front[SIM_DISKS_MAX];
    if (s->disks < 1 || s->disks > SIM_DISKS_MAX) {
        snprintf(err, errlen, "disks: %d is outside [1, %d]", s->disks, SIM_DISKS_MAX);
        return -1;
    }
    if (from < 1 || to < from || to > s->disks) {
        snprintf(err, errlen,
                 "radial: disks %d to %d: say FROM <= TO within 1..%d (numbered from the bottom)", from, to,
                 s->disks);
        return -1;
    }
    if (!isfinite(metres) || fabs(metres) > RADIAL_LIMIT_M) {
        snprintf(err, errlen, "radial: a change of %g m is not within +-%g m", metres, RADIAL_LIMIT_M);
        return -1;
    }
    if (sim_scene_radial_changes(s, front, err, errlen) != 0)
        return -1;
    for (int i = from; i <= to; i++)
        front[i - 1] = metres;
    char text[SIM_TEXT_MAX] = "";
    size_t used = 0;
    for (int i = 0; i < s->disks;) {
        int j = i;
        while (j + 1 < s->disks && front[j + 1] == front[i])
            j++;
        if (front[i] != 0) {
            char num[40], item[64];
            format_metres(num, sizeof num, front[i]);
            if (i == j)
                snprintf(item, sizeof item, "%s%d:%s", used ? "," : "", i + 1, num);
            else
                snprintf(item, sizeof item, "%s%d-%d:%s", used ? "," : "", i + 1, j + 1, num);
            size_t n = strlen(item);
            if (used + n >= sizeof text) {
                snprintf(err, errlen, "radial_m: too many separate changes to write in %d bytes",
                         SIM_TEXT_MAX - 1);
                return -1;
            }
            memcpy(text + used, item, n + 1);
            used += n;
        }
        i = j + 1;
    }
    return sim_scene_set(s, "radial_m", text, err, errlen);
}
