/* The control endpoint's commands (see uwbemu --help): change the scene
 * while running, turn faults on and off, read the board's state and the
 * log of triggers. Every reply is one JSON object with a "class". */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu.h"

static char *print_and_free(cJSON *o)
{
    char *text = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    return text;
}

static char *reply_error(const char *fmt, const char *a, const char *b)
{
    char msg[768];
    snprintf(msg, sizeof msg, fmt, a, b ? b : "");
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "ERROR");
    cJSON_AddStringToObject(o, "message", msg);
    return print_and_free(o);
}

static cJSON *reply_ok(const char *command)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "OK");
    cJSON_AddStringToObject(o, "command", command);
    return o;
}

static char *status(struct emu_board *b)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "STATUS");
    cJSON_AddNumberToObject(o, "position_mm", b->steps / b->steps_per_mm);
    cJSON_AddNumberToObject(o, "y_m", emu_board_y_m(b));
    cJSON_AddNumberToObject(o, "steps", (double)b->steps);
    cJSON_AddNumberToObject(o, "steps_per_mm", b->steps_per_mm);
    cJSON_AddNumberToObject(o, "home_y_mm", b->home_y_mm);
    cJSON_AddBoolToObject(o, "invert_dir", b->invert_dir);
    cJSON_AddNumberToObject(o, "steps_counted", (double)b->steps_counted);
    cJSON_AddNumberToObject(o, "steps_stalled", (double)b->steps_stalled);
    cJSON_AddNumberToObject(o, "steps_lost", (double)b->steps_lost);
    cJSON_AddNumberToObject(o, "steps_while_disabled", (double)b->steps_while_disabled);
    cJSON *lines = cJSON_AddObjectToObject(o, "lines");
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        cJSON_AddNumberToObject(lines, uwb_gpio_line_name(i),
                                i == UWB_LINE_HOME ? emu_board_home_active(b) : b->line[i]);
    cJSON_AddBoolToObject(o, "digitiser_connected", b->digitiser != NULL);
    cJSON_AddBoolToObject(o, "armed", b->armed);
    cJSON_AddNumberToObject(o, "triggers", (double)b->triggers);
    cJSON_AddNumberToObject(o, "frames_sent", (double)b->frames_sent);
    cJSON_AddNumberToObject(o, "last_trace_y_m", b->last_trace_y_m);
    cJSON_AddNumberToObject(o, "samples", b->scene.samples);
    cJSON_AddNumberToObject(o, "sample_interval_s", b->scene.sample_interval_s);
    cJSON *faults = cJSON_AddObjectToObject(o, "faults");
    for (int i = 0; i < EMU_FAULT_COUNT; i++) {
        char text[32];
        emu_fault_describe(&b->fault[i], text, sizeof text);
        cJSON_AddStringToObject(faults, emu_fault_name(i), text);
    }
    return print_and_free(o);
}

static char *log_reply(struct emu_board *b)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "LOG");
    cJSON *entries = cJSON_AddArrayToObject(o, "entries");
    for (size_t i = 0; i < b->log_len; i++) {
        const struct emu_log_entry *e = &b->log[i];
        cJSON *item = cJSON_CreateObject();
        cJSON_AddNumberToObject(item, "trigger", (double)e->trigger);
        cJSON_AddNumberToObject(item, "sequence", (double)e->sequence);
        cJSON_AddNumberToObject(item, "y_m", e->y_m);
        cJSON_AddNumberToObject(item, "steps", (double)e->steps);
        cJSON_AddStringToObject(item, "result", e->result);
        cJSON_AddItemToArray(entries, item);
    }
    return print_and_free(o);
}

static char *set_scene(struct emu_board *b, const char *key, const char *value)
{
    struct sim_scene scene = b->scene;
    char err[512];
    if (sim_scene_set(&scene, key, value, err, sizeof err) != 0 ||
        emu_board_set_scene(b, &scene, err, sizeof err) != 0)
        return reply_error("set: %s%s", err, NULL);
    cJSON *o = reply_ok("set");
    cJSON_AddStringToObject(o, "key", key);
    char now[SIM_TEXT_MAX];
    sim_scene_get(&b->scene, sim_param_find(key), now, sizeof now);
    cJSON_AddStringToObject(o, "value", now);
    return print_and_free(o);
}

/* A number in mm from text that must be nothing else. */
static int parse_mm(const char *text, double *mm)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end || errno || !isfinite(v))
        return -1;
    *mm = v;
    return 0;
}

/* A whole disk number from 1 up. */
static int parse_disk(const char *text, int *disk)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (!isdigit((unsigned char)text[0]) || *end || errno || v < 1 || v > SIM_DISKS_MAX)
        return -1;
    *disk = (int)v;
    return 0;
}

static char *scene_changed(struct emu_board *b, struct sim_scene *scene, const char *key)
{
    char err[512];
    if (emu_board_set_scene(b, scene, err, sizeof err) != 0)
        return reply_error("set: %s%s", err, NULL);
    const struct sim_param *p = sim_param_find(key);
    char now[SIM_TEXT_MAX];
    sim_scene_get(&b->scene, p, now, sizeof now);
    cJSON *o = reply_ok("set");
    cJSON_AddStringToObject(o, "key", p->name);
    cJSON_AddStringToObject(o, "value", now);
    return print_and_free(o);
}

/* set radial FROM TO MM: the fronts of disks FROM..TO (1 = the bottom one)
 * moved MM toward the antennas (negative: away), the others kept. */
static char *set_radial(struct emu_board *b, const char *value)
{
    char from_text[32], to_text[32], mm_text[64], extra[2];
    int from, to;
    double mm;
    char err[512];
    if (sscanf(value, "%31s %31s %63s %1s", from_text, to_text, mm_text, extra) != 3)
        return reply_error("set radial '%s': say `set radial FROM TO MM` (disks numbered from 1 at the "
                           "bottom; MM + toward the antennas, - away)%s",
                           value, NULL);
    if (parse_disk(from_text, &from) != 0 || parse_disk(to_text, &to) != 0)
        return reply_error("set radial '%s': FROM and TO must be disk numbers from 1 (the bottom disk)%s",
                           value, NULL);
    if (parse_mm(mm_text, &mm) != 0)
        return reply_error("set radial: '%s' is not a number of mm%s", mm_text, NULL);
    struct sim_scene scene = b->scene;
    if (sim_scene_set_radial(&scene, from, to, mm / 1000.0, err, sizeof err) != 0)
        return reply_error("set %s%s", err, NULL);
    return scene_changed(b, &scene, "radial_m");
}

/* set face_tilt MM: the top disk's front MM nearer than the bottom's. */
static char *set_face_tilt(struct emu_board *b, const char *value)
{
    double mm;
    char text[32], err[512];
    if (parse_mm(value, &mm) != 0)
        return reply_error("set face_tilt: '%s' is not a number of mm (the top disk's front this much "
                           "nearer the antennas than the bottom's)%s",
                           value, NULL);
    snprintf(text, sizeof text, "%.17g", mm / 1000.0);
    struct sim_scene scene = b->scene;
    if (sim_scene_set(&scene, "face_tilt_m", text, err, sizeof err) != 0)
        return reply_error("set %s%s", err, NULL);
    return scene_changed(b, &scene, "face_tilt_m");
}

static char *get_scene(struct emu_board *b, const char *key)
{
    const struct sim_param *p = sim_param_find(key);
    if (!p)
        return reply_error("get: no scene parameter '%s'%s", key, NULL);
    char value[SIM_TEXT_MAX];
    sim_scene_get(&b->scene, p, value, sizeof value);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "VALUE");
    cJSON_AddStringToObject(o, "key", p->name);
    cJSON_AddStringToObject(o, "value", value);
    return print_and_free(o);
}

static int parse_count(const char *text, unsigned *n)
{
    char *end;
    errno = 0;
    unsigned long v = strtoul(text, &end, 10);
    if (!*text || *end || errno || v < 1 || v > 1000000 || text[0] == '-')
        return -1;
    *n = (unsigned)v;
    return 0;
}

/* fault NAME on|off|every N|next N */
static char *fault(struct emu_board *b, const char *name, const char *mode, const char *count)
{
    int id = emu_fault_find(name);
    if (id < 0)
        return reply_error("fault: no fault '%s' (crc, truncate, drop, silent, disconnect, home-never, "
                           "home-stuck, lose-steps)%s",
                           name, NULL);
    struct emu_fault f = {0};
    if (strcmp(mode, "on") == 0 && !count[0]) {
        f.mode = EMU_FAULT_ON;
    } else if (strcmp(mode, "off") == 0 && !count[0]) {
        f.mode = EMU_FAULT_OFF;
    } else if ((strcmp(mode, "every") == 0 || strcmp(mode, "next") == 0) && parse_count(count, &f.n) == 0) {
        f.mode = mode[0] == 'e' ? EMU_FAULT_EVERY : EMU_FAULT_NEXT;
    } else {
        return reply_error("fault %s: say on, off, every N or next N (N from 1), not '%s'", name, mode);
    }
    b->fault[id] = f;
    cJSON *o = reply_ok("fault");
    char text[32];
    emu_fault_describe(&f, text, sizeof text);
    cJSON_AddStringToObject(o, "fault", name);
    cJSON_AddStringToObject(o, "mode", text);
    return print_and_free(o);
}

/* board steps_per_mm|home_y_mm|invert_dir|position_mm VALUE */
static char *board(struct emu_board *b, const char *key, const char *value)
{
    char *end;
    errno = 0;
    double v = strtod(value, &end);
    if (!*value || *end || errno)
        return reply_error("board %s: '%s' is not a number", key, value);
    if (strcmp(key, "steps_per_mm") == 0 && v > 0 && v <= 1e5) {
        b->steps_per_mm = v;
    } else if (strcmp(key, "home_y_mm") == 0) {
        b->home_y_mm = v;
    } else if (strcmp(key, "invert_dir") == 0 && (v == 0 || v == 1)) {
        b->invert_dir = (int)v;
    } else if (strcmp(key, "position_mm") == 0) {
        b->steps = (long)(v * b->steps_per_mm + (v >= 0 ? 0.5 : -0.5));
    } else {
        return reply_error(
            "board: '%s' is not steps_per_mm (> 0), home_y_mm, invert_dir (0/1) or position_mm%s", key, NULL);
    }
    cJSON *o = reply_ok("board");
    cJSON_AddStringToObject(o, "key", key);
    cJSON_AddNumberToObject(o, "value", v);
    return print_and_free(o);
}

static char *truth(struct emu_board *b)
{
    char *json;
    if (sim_truth_json(&b->scene, &json) != 0)
        return reply_error("truth: out of memory%s%s", "", NULL);
    cJSON *o = cJSON_Parse(json);
    free(json);
    if (!o)
        return reply_error("truth: out of memory%s%s", "", NULL);
    cJSON_AddStringToObject(o, "class", "TRUTH");
    return print_and_free(o);
}

static const char help_text[] =
    "status | log | log clear | set KEY VALUE | set radial FROM TO MM | set face_tilt MM | get KEY | "
    "fault NAME on|off|every N|next N | "
    "board steps_per_mm|home_y_mm|invert_dir|position_mm VALUE | input event 0|1 | truth | quit";

char *emu_control_command(struct emu_board *b, const char *line)
{
    /* Split off up to three words; a `set` value is the rest of the line. */
    char words[3][128] = {"", "", ""};
    const char *p = line, *rest = "";
    for (int i = 0; i < 3; i++) {
        while (isspace((unsigned char)*p))
            p++;
        size_t n = strcspn(p, " \t\r\n");
        if (n >= sizeof words[i])
            return reply_error("'%.60s...': word too long%s", p, NULL);
        memcpy(words[i], p, n);
        words[i][n] = '\0';
        p += n;
        if (i == 1) {
            rest = p;
            while (isspace((unsigned char)*rest))
                rest++;
        }
    }
    while (isspace((unsigned char)*p))
        p++;
    char value[SIM_TEXT_MAX];
    snprintf(value, sizeof value, "%s", rest);
    size_t vl = strlen(value);
    while (vl && isspace((unsigned char)value[vl - 1]))
        value[--vl] = '\0';

    const char *cmd = words[0];
    if (strcmp(cmd, "status") == 0 && !words[1][0])
        return status(b);
    if (strcmp(cmd, "log") == 0 && !words[1][0])
        return log_reply(b);
    if (strcmp(cmd, "log") == 0 && strcmp(words[1], "clear") == 0 && !words[2][0]) {
        b->log_len = 0;
        return print_and_free(reply_ok("log clear"));
    }
    if (strcmp(cmd, "set") == 0 && strcmp(words[1], "radial") == 0 && value[0])
        return set_radial(b, value);
    if (strcmp(cmd, "set") == 0 && strcmp(words[1], "face_tilt") == 0 && value[0])
        return set_face_tilt(b, value);
    if (strcmp(cmd, "set") == 0 && words[1][0] && value[0])
        return set_scene(b, words[1], value);
    if (strcmp(cmd, "get") == 0 && words[1][0] && !words[2][0])
        return get_scene(b, words[1]);
    if (strcmp(cmd, "fault") == 0 && words[1][0] && words[2][0])
        return fault(b, words[1], words[2], *p ? p : "");
    if (strcmp(cmd, "board") == 0 && words[1][0] && words[2][0] && !*p)
        return board(b, words[1], words[2]);
    if (strcmp(cmd, "input") == 0 && words[1][0] && words[2][0] && !*p) {
        if ((strcmp(words[2], "0") != 0 && strcmp(words[2], "1") != 0) ||
            emu_gpio_set_input(b, words[1], words[2][0] - '0') != 0)
            return reply_error("input: say `input event 0` or `input event 1`, not '%.60s'%s", line, NULL);
        cJSON *o = reply_ok("input");
        cJSON_AddStringToObject(o, "line", words[1]);
        cJSON_AddNumberToObject(o, "value", words[2][0] - '0');
        return print_and_free(o);
    }
    if (strcmp(cmd, "truth") == 0 && !words[1][0])
        return truth(b);
    if (strcmp(cmd, "quit") == 0 && !words[1][0]) {
        b->quit = 1;
        return print_and_free(reply_ok("quit"));
    }
    if (strcmp(cmd, "help") == 0) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "class", "HELP");
        cJSON_AddStringToObject(o, "commands", help_text);
        return print_and_free(o);
    }
    return reply_error("unknown or incomplete command '%.80s'; commands: %s", line, help_text);
}
