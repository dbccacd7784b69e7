/* Fuzzing the emulated board's side of the emulated-GPIO protocol
 * (emu_gpio_line in tools/emuboard/gpio_server.c): the input is what a
 * host sends on the GPIO endpoint. uwbemu cuts it into lines in a static
 * function of tools/emuboard/main.c (read_lines); this harness cuts the
 * same way (at most 1023 bytes, the rest of a longer line dropped,
 * trailing '\r's removed) and hands each line over.
 *
 * The board has no scene: nothing here arms its digitiser, so a trigger
 * is only counted and logged, never simulated.
 *
 * Contract: a reply is nothing or one line ("ok ", "val " or "err ")
 * ending in its only '\n'; the outputs hold 0 or 1; every rising STEP
 * edge is counted once, as a step or as a step lost to a disabled motor. */
#include <string.h>

#include "emuboard/emu.h"
#include "fuzz_harness.h"

#define LINE_MAX_BYTES 1024

static int check_reply(const char *reply, size_t replylen, char *why, size_t whylen)
{
    const char *end = memchr(reply, '\0', replylen);
    if (!end)
        return fuzz_broken(why, whylen, "reply unterminated");
    if (end == reply)
        return FUZZ_ACCEPTED;
    const char *newline = strchr(reply, '\n');
    if (newline != end - 1)
        return fuzz_broken(why, whylen, "reply is not one line: '%.80s'", reply);
    if (strncmp(reply, "ok ", 3) && strncmp(reply, "val ", 4) && strncmp(reply, "err ", 4))
        return fuzz_broken(why, whylen, "reply of no known kind: '%.80s'", reply);
    return FUZZ_ACCEPTED;
}

static int handle_line(struct emu_board *b, const char *line, unsigned long *rising_steps, int *understood,
                       char *why, size_t whylen)
{
    char reply[256];
    int step_before = b->line[UWB_LINE_STEP];
    memset(reply, 'x', sizeof reply);
    emu_gpio_line(b, line, reply, sizeof reply);
    if (check_reply(reply, sizeof reply, why, whylen) == FUZZ_BROKEN)
        return FUZZ_BROKEN;
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if (b->line[i] != 0 && b->line[i] != 1)
            return fuzz_broken(why, whylen, "line %s holds %d", uwb_gpio_line_name(i), b->line[i]);
    if (b->line[UWB_LINE_HOME])
        return fuzz_broken(why, whylen, "the host drove the home input");
    *rising_steps += !step_before && b->line[UWB_LINE_STEP];
    if (b->steps_counted + b->steps_while_disabled != *rising_steps)
        return fuzz_broken(why, whylen, "%lu rising STEP edges, %lu steps + %lu lost", *rising_steps,
                           b->steps_counted, b->steps_while_disabled);
    /* Understood: a set (no reply), or a hello or get answered without err. */
    if (reply[0] ? strncmp(reply, "err ", 4) != 0 : line[0] != '\0')
        ++*understood;
    return FUZZ_ACCEPTED;
}

int fuzz_gpio_board_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    /* What emu_board_init sets besides the scene. */
    static struct emu_board board;
    memset(&board, 0, sizeof board);
    board.steps_per_mm = 100;
    board.home_y_mm = -20;

    char line[LINE_MAX_BYTES];
    size_t len = 0;
    int overlong = 0, understood = 0, rc = FUZZ_ACCEPTED;
    unsigned long rising_steps = 0;
    why[0] = '\0';
    for (size_t i = 0; i < size && rc != FUZZ_BROKEN; i++) {
        char c = (char)data[i];
        if (c == '\n') {
            if (!overlong) {
                while (len && line[len - 1] == '\r')
                    len--;
                line[len] = '\0';
                rc = handle_line(&board, line, &rising_steps, &understood, why, whylen);
            }
            len = 0;
            overlong = 0;
        } else if (len + 1 < sizeof line) {
            line[len++] = c;
        } else {
            overlong = 1;
        }
    }
    free(board.log);
    if (rc == FUZZ_BROKEN)
        return rc;
    if (understood)
        return FUZZ_ACCEPTED;
    snprintf(why, whylen, "no line understood in %zu bytes", size);
    return FUZZ_REJECTED;
}

UWB_FUZZ_TARGET(fuzz_gpio_board_input)
