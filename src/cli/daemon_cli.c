/* uwbd --config / --check-config / --config-keys: the daemon's command line. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "uwb/cli.h"
#include "daemon/daemon.h"
#include "control/exit_codes.h"
#include "util/log.h"

void uwbd_daemon_usage(FILE *f)
{
    fprintf(
        f,
        "usage: uwbd --config FILE [options]        run the appliance daemon (foreground)\n"
        "       uwbd --check-config FILE [options]  validate FILE with the overrides below, then exit\n"
        "       uwbd --config-keys[=man]            print every configuration key (Markdown table, or the\n"
        "                                           uwbd.json(5) manual page)\n"
        "\n"
        "  --state-dir DIR          override state_dir\n"
        "  --interval S             override schedule.interval_s (0: scan only on request)\n"
        "  --console ENDPOINT       override console.endpoint (\"\": no console)\n"
        "  --control-socket PATH    override control.socket\n"
        "  --set KEY=VALUE          override any key; VALUE is JSON, a bare word is a string\n"
        "  --allow-root             allow running as root (allow_root = true)\n"
        "  -v, --verbose            log debug lines too\n"
        "  --syslog                 also log to syslog (under systemd stderr already goes to the journal)\n"
        "\n"
        "SIGTERM/SIGINT stop the daemon safely (a running scan is stopped, the hardware left safe);\n"
        "SIGHUP reloads FILE between scans. Exit status: 0 stopped by a signal or config valid; 64 bad\n"
        "usage; 69 GPIO chip missing; 71 system error; 72 GPIO line missing or busy; 73 state directory\n"
        "or control socket cannot be created, or another uwbd uses them; 74 digitiser port missing;\n"
        "77 run as root without allow_root; 78 configuration malformed or incomplete (the message\n"
        "names the key).\n");
}

int uwbd_wants_daemon(int argc, char **argv)
{
    static const char *const flags[] = {"--config", "--check-config", "--config-keys"};
    for (int i = 1; i < argc; i++)
        for (size_t j = 0; j < sizeof flags / sizeof flags[0]; j++) {
            size_t n = strlen(flags[j]);
            if (strncmp(argv[i], flags[j], n) == 0 && (argv[i][n] == '\0' || argv[i][n] == '='))
                return 1;
        }
    return 0;
}

enum {
    OPT_CONFIG = 256,
    OPT_CHECK,
    OPT_KEYS,
    OPT_STATE_DIR,
    OPT_INTERVAL,
    OPT_CONSOLE,
    OPT_CONTROL,
    OPT_SET,
    OPT_ALLOW_ROOT,
    OPT_SYSLOG
};

static int add_override(struct uwbd_options *o, const char *key, const char *value)
{
    if (o->n_overrides == UWBD_MAX_OVERRIDES) {
        fprintf(stderr, "uwbd: more than %d overrides\n", UWBD_MAX_OVERRIDES);
        return -1;
    }
    o->overrides[o->n_overrides++] = (struct uwbd_override){.key = key, .value = value};
    return 0;
}

/* --set KEY=VALUE: the key is cut out of argv in place. */
static int add_set(struct uwbd_options *o, char *arg)
{
    // NOLINTNEXTLINE(clang-analyzer-core.NonNullParamChecker): getopt_long sets optarg for a required_argument
    char *eq = strchr(arg, '=');
    if (!eq || eq == arg) {
        fprintf(stderr, "uwbd: --set: '%s' is not KEY=VALUE\n", arg);
        return -1;
    }
    *eq = '\0';
    return add_override(o, arg, eq + 1);
}

/* An override given on its own option (a path, an endpoint): a string even
 * where it would read as JSON, so quoted and escaped by cJSON. The text
 * lives as long as the options, i.e. the process. */
static int add_string_override(struct uwbd_options *o, const char *key, const char *text)
{
    cJSON *string = cJSON_CreateString(text);
    char *json = string ? cJSON_PrintUnformatted(string) : NULL;
    cJSON_Delete(string);
    if (!json) {
        fprintf(stderr, "uwbd: out of memory\n");
        return -1;
    }
    int rc = add_override(o, key, json);
    if (rc != 0)
        free(json);
    return rc;
}

int uwbd_daemon_main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"config", required_argument, 0, OPT_CONFIG},
        {"check-config", required_argument, 0, OPT_CHECK},
        {"config-keys", optional_argument, 0, OPT_KEYS},
        {"state-dir", required_argument, 0, OPT_STATE_DIR},
        {"interval", required_argument, 0, OPT_INTERVAL},
        {"console", required_argument, 0, OPT_CONSOLE},
        {"control-socket", required_argument, 0, OPT_CONTROL},
        {"set", required_argument, 0, OPT_SET},
        {"allow-root", no_argument, 0, OPT_ALLOW_ROOT},
        {"verbose", no_argument, 0, 'v'},
        {"syslog", no_argument, 0, OPT_SYSLOG},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0},
    };
    static struct uwbd_options opt;
    memset(&opt, 0, sizeof opt);
    opt.log_level = UWBD_LOG_INFO;
    const char *check = NULL;
    int keys = 0, c, bad = 0;
    opterr = 0; /* one line of our own instead of getopt's and the usage */
    while ((c = getopt_long(argc, argv, "vh", longopts, NULL)) != -1) {
        switch (c) {
        case OPT_CONFIG: opt.config_path = optarg; break;
        case OPT_CHECK: check = optarg; break;
        case OPT_KEYS:
            if (!optarg || strcmp(optarg, "markdown") == 0) {
                keys = 1;
            } else if (strcmp(optarg, "man") == 0) {
                keys = 2;
            } else {
                fprintf(stderr, "uwbd: --config-keys=%s: the format is markdown or man; see uwbd --help\n",
                        optarg);
                return UWBD_EXIT_USAGE;
            }
            break;
        case OPT_STATE_DIR: bad |= add_string_override(&opt, "state_dir", optarg); break;
        case OPT_INTERVAL: bad |= add_override(&opt, "schedule.interval_s", optarg); break;
        case OPT_CONSOLE: bad |= add_string_override(&opt, "console.endpoint", optarg); break;
        case OPT_CONTROL: bad |= add_string_override(&opt, "control.socket", optarg); break;
        case OPT_SET: bad |= add_set(&opt, optarg); break;
        case OPT_ALLOW_ROOT: bad |= add_override(&opt, "allow_root", "true"); break;
        case 'v': opt.log_level = UWBD_LOG_DEBUG; break;
        case OPT_SYSLOG: opt.use_syslog = 1; break;
        case 'h': uwbd_daemon_usage(stdout); return UWBD_EXIT_OK;
        default: uwb_cli_option_error("uwbd", "uwbd --help", argv, argc, longopts); return UWBD_EXIT_USAGE;
        }
    }
    if (bad)
        return UWBD_EXIT_USAGE;
    if (optind < argc) {
        uwb_cli_unexpected_argument("uwbd", argv, optind, argc);
        return UWBD_EXIT_USAGE;
    }
    if (keys == 2) {
        if (uwbd_config_print_keys_man(stdout) != 0) {
            fprintf(stderr, "uwbd: cannot build the manual page from the key table\n");
            return UWBD_EXIT_OS;
        }
        return UWBD_EXIT_OK;
    }
    if (keys) {
        uwbd_config_print_keys_markdown(stdout);
        return UWBD_EXIT_OK;
    }
    if (check && opt.config_path) {
        fprintf(stderr, "uwbd: give either --config or --check-config\n");
        return UWBD_EXIT_USAGE;
    }
    if (check) {
        static struct uwbd_config cfg;
        char err[1024];
        if (uwbd_config_load(check, opt.overrides, opt.n_overrides, &cfg, err, sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            return UWBD_EXIT_CONFIG;
        }
        if (uwbd_config_check_system(&cfg, check, err, sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            return UWBD_EXIT_CONFIG;
        }
        printf("%s: configuration valid\n", check);
        return UWBD_EXIT_OK;
    }
    if (!opt.config_path) {
        fprintf(stderr, "uwbd: --config FILE is required\n");
        return UWBD_EXIT_USAGE;
    }
    return uwbd_daemon_run(&opt);
}
