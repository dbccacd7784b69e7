/* Fuzzing `uwbd --set KEY=VALUE` (issue 17): the input is one --set
 * argument, split at its first '=' as the command line does, applied as an
 * override on the emulated sample configuration through the loader.
 *
 * Contract: the override is taken (and the config is then whole) or
 * refused with a message naming the configuration. */
#include <string.h>

#include "fuzz_harness.h"
#include "config/config_load.h"

static const char sample[] =
    "{\"state_dir\": \"run/state\", \"control\": {\"socket\": \"run/control.sock\"},"
    " \"gpio\": {\"backend\": \"emulated\", \"endpoint\": \"unix:run/gpio.sock\"},"
    " \"digitiser\": {\"endpoint\": \"unix:run/digitiser.sock\", \"samples\": 2048, \"sample_interval_ps\": "
    "10,"
    " \"t0_ps\": -1000},"
    " \"carriage\": {\"steps_per_mm\": 100, \"travel_mm\": 650, \"home_offset_mm\": -20},"
    " \"scan\": {\"positions\": 21, \"first_position_mm\": 0, \"step_mm\": 30},"
    " \"geometry\": {\"tx_mm\": [-20, 0], \"rx_mm\": [20, 0], \"eps_r\": 2.2}}";

int fuzz_set_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    char arg[512];
    if (size >= sizeof arg || memchr(data, '\0', size)) {
        snprintf(why, whylen, "not one command-line argument");
        return FUZZ_REJECTED;
    }
    memcpy(arg, data, size);
    arg[size] = '\0';
    char *eq = strchr(arg, '=');
    if (!eq) {
        snprintf(why, whylen, "no '=' in --set %s", arg);
        return FUZZ_REJECTED;
    }
    *eq = '\0';
    struct uwbd_override o = {arg, eq + 1};
    static struct uwbd_config cfg;
    char err[1024] = "";
    if (uwbd_config_parse(sample, strlen(sample), "fuzz.json", &o, 1, &cfg, err, sizeof err) != 0) {
        if (!err[0])
            return fuzz_broken(why, whylen, "--set refused without a message");
        snprintf(why, whylen, "%s", err);
        return FUZZ_REJECTED;
    }
    if (!memchr(cfg.state_dir, '\0', sizeof cfg.state_dir) || !cfg.state_dir[0] || !cfg.control_socket[0])
        return fuzz_broken(why, whylen, "accepted a config without its paths");
    return FUZZ_ACCEPTED;
}

UWB_FUZZ_TARGET(fuzz_set_input)
