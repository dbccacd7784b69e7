/* The board's side of the emulated-GPIO protocol (board/emulated-gpio.md):
 * STEP rising edges move the carriage one microstep in the DIR direction
 * while ENABLE is high, between the end stops below the switch and above
 * the travel; a TRIGGER rising edge fires the pulser, HOME reads closed at
 * or below the switch. */
#include <stdio.h>
#include <string.h>

#include "emu.h"

static int find_line(const char *name)
{
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if (strcmp(name, uwb_gpio_line_name(i)) == 0)
            return i;
    return -1;
}

static void set_line(struct emu_board *b, int line, int value)
{
    int rising = value && !b->line[line];
    b->line[line] = value;
    if (!rising)
        return;
    if (line == UWB_LINE_STEP) {
        /* An unpowered motor does not turn: steps without ENABLE are lost,
         * as they would be on the bench. */
        if (!b->line[UWB_LINE_ENABLE]) {
            b->steps_while_disabled++;
            return;
        }
        int up = b->line[UWB_LINE_DIR] ^ b->invert_dir;
        b->steps_counted++;
        /* The carriage's mechanical stops, a little below the switch and
         * just above the travel: a home search with a dead switch, or a
         * daemon stepping too far up, stalls there as on a real rig instead
         * of driving on without end; the stalled motor does not move. */
        if (!up && b->steps <= -(long)(EMU_END_STOP_BELOW_HOME_MM * b->steps_per_mm)) {
            b->steps_stalled++;
            return;
        }
        if (up && b->steps >= (long)(EMU_END_STOP_ABOVE_HOME_MM * b->steps_per_mm)) {
            b->steps_stalled++;
            return;
        }
        if (up && emu_fault_strikes(&b->fault[EMU_FAULT_LOSE_STEPS])) {
            b->steps_lost++; /* the belt slips: the driver stepped, the carriage stayed */
            return;
        }
        b->steps += up ? 1 : -1;
    } else if (line == UWB_LINE_TRIGGER) {
        emu_digitiser_trigger(b);
    }
}

void emu_gpio_line(struct emu_board *b, const char *text, char *reply, size_t replylen)
{
    /* Words only: a level is the one character 0 or 1, nothing to convert. */
    char cmd[16], name[16], level[16], extra[2];
    reply[0] = '\0';
    int n = sscanf(text, "%15s %15s %15s %1s", cmd, name, level, extra);
    if (n == 3 && strcmp(cmd, "set") == 0) {
        int line = find_line(name);
        int value = strcmp(level, "1") == 0 ? 1 : strcmp(level, "0") == 0 ? 0 : -1;
        if (line < 0 || uwb_gpio_line_is_input(line) || value < 0)
            snprintf(reply, replylen,
                     "err cannot set '%.60s': outputs are trigger, step, dir, enable, watch, alarm, fault; "
                     "values 0 or 1\n",
                     text);
        else
            set_line(b, line, value);
        return;
    }
    if (n == 2 && strcmp(cmd, "get") == 0) {
        int line = find_line(name);
        if (line < 0)
            snprintf(reply, replylen, "err no line '%.20s'\n", name);
        else
            snprintf(reply, replylen, "val %s %d\n", name,
                     line == UWB_LINE_HOME ? emu_board_home_active(b) : b->line[line]);
        return;
    }
    if (n == 2 && strcmp(cmd, "hello") == 0) {
        if (strcmp(name, EMU_GPIO_PROTOCOL) == 0)
            snprintf(reply, replylen, "ok %s uwbemu %s\n", EMU_GPIO_PROTOCOL, EMU_VERSION);
        else
            snprintf(reply, replylen, "err protocol '%.20s' not spoken here; this is %s\n", name,
                     EMU_GPIO_PROTOCOL);
        return;
    }
    if (text[0])
        snprintf(reply, replylen, "err unknown command '%.60s'\n", text);
}

void emu_gpio_released(struct emu_board *b, unsigned lines)
{
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if ((lines & UWB_GPIO_LINE_BIT(i)) && !uwb_gpio_line_is_input(i))
            b->line[i] = 0;
}

int emu_gpio_set_input(struct emu_board *b, const char *name, int value)
{
    int line = find_line(name);
    if (line != UWB_LINE_EVENT || (value != 0 && value != 1))
        return -1;
    b->line[line] = value;
    return 0;
}
