/* uwbemu: the emulated board (see emu.h), its command line and its event
 * loop; or, with --ctl, a one-shot client of a running board's control
 * endpoint. */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "emu.h"

#define MAX_CONTROL_CLIENTS 8
#define LINE_MAX_BYTES 1024
#define WRITE_TIMEOUT_MS 2000
#define CTL_TIMEOUT_MS 30000

static volatile sig_atomic_t stop_signal;

static void on_signal(int sig)
{
    stop_signal = sig;
}

static void usage(FILE *out)
{
    fprintf(
        out,
        "usage: uwbemu --gpio ENDPOINT --digitiser ENDPOINT [--control ENDPOINT] [options]\n"
        "       uwbemu --ctl ENDPOINT 'COMMAND'\n"
        "\n"
        "The emulated board: plays the pulser, the digitiser and the antenna carriage\n"
        "for uwbd. Endpoints are listened on (unix:PATH or tcp:HOST:PORT); a new\n"
        "connection replaces the current one, so a peer that drops can come back.\n"
        "\n"
        "  --gpio ENDPOINT        emulated-GPIO protocol (board/emulated-gpio.md)\n"
        "  --digitiser ENDPOINT   digitiser frame protocol (board/digitiser-protocol.md)\n"
        "  --control ENDPOINT     control commands, one line each, one JSON reply line\n"
        "  --site-io ENDPOINT     the site's lines (alarm contacts watch, alarm, fault; event input)\n"
        "                         on the emulated-GPIO protocol, for uwbd's gpio.site_endpoint\n"
        "  --scene FILE           uwbsim scene JSON (tools/uwbsim/scenes/); default: uwbsim's defaults\n"
        "  --set KEY=VALUE        any uwbsim scene parameter (repeatable), e.g. --set displacement_m=0.012\n"
        "  --seed N               noise seed (default 1)\n"
        "  --steps-per-mm X       the carriage's microsteps per mm (default 100)\n"
        "  --home-y-mm Y          y of the home switch in scene coordinates, mm (default -20)\n"
        "  --start-mm Z           carriage position above home at start, mm (default 50)\n"
        "  --invert-dir           wiring fault: DIR high moves the carriage down\n"
        "  -v, --verbose          log every trigger to stderr\n"
        "  --ctl ENDPOINT CMD     send one control command to a running uwbemu, print the\n"
        "                         reply; exit 0, or 1 if the reply's class is ERROR\n"
        "  --help                 this text\n"
        "\n"
        "Control commands:\n"
        "  status                 carriage position, lines, triggers, frames, faults (class STATUS)\n"
        "  log | log clear        for every trigger: sequence, carriage y_m and steps, result (class LOG)\n"
        "  set KEY VALUE          change a scene parameter and rebuild the simulation (e.g. set "
        "displacement_m 0.012)\n"
        "  set radial FROM TO MM  move the fronts of disks FROM..TO (1 = the bottom disk) MM toward the\n"
        "                         antennas (negative: away, a dent); other disks keep theirs; 0 undoes\n"
        "  set face_tilt MM       the top disk's front MM nearer than the bottom's, linear between\n"
        "                         (both rewrite the scene's radial_m / face_tilt_m, in m)\n"
        "  get KEY                a scene parameter's value\n"
        "  fault NAME MODE        NAME: crc, truncate, drop, silent, disconnect, home-never, home-stuck,\n"
        "                         lose-steps (upward steps that strike do not move the carriage);\n"
        "                         MODE: on, off, every N, next N\n"
        "  board KEY VALUE        steps_per_mm, home_y_mm, invert_dir (0/1), position_mm (move the "
        "carriage)\n"
        "  input event 0|1        the event input (a protection relay's trip contact) open or closed\n"
        "  truth                  the scene's true winding edges (class TRUTH)\n"
        "  quit                   stop the board\n");
}

/* A connected peer whose input is split into lines. */
struct line_peer {
    struct uwb_link *link;
    char buf[LINE_MAX_BYTES];
    size_t len;
    int overlong; /* discarding the rest of a line that did not fit */
};

typedef void (*line_fn)(struct emu_board *b, struct line_peer *peer, const char *line);

/* Reads what is there and hands over each complete line; -1 when the
 * peer has gone (its link is then closed). */
static int read_lines(struct emu_board *b, struct line_peer *peer, line_fn handle, const char *what)
{
    char chunk[65536], err[512];
    ssize_t n = uwb_link_read(peer->link, chunk, sizeof chunk, 0, err, sizeof err);
    if (n == UWB_LINK_ERR_TIMEOUT)
        return 0;
    if (n < 0) {
        if (b->verbose)
            fprintf(stderr, "uwbemu: %s: %s\n", what, err);
        uwb_link_close(peer->link);
        peer->link = NULL;
        peer->len = 0;
        return -1;
    }
    for (ssize_t i = 0; i < n && peer->link; i++) {
        char c = chunk[i];
        if (c == '\n') {
            if (!peer->overlong) {
                while (peer->len && peer->buf[peer->len - 1] == '\r')
                    peer->len--;
                peer->buf[peer->len] = '\0';
                handle(b, peer, peer->buf);
            }
            peer->len = 0;
            peer->overlong = 0;
        } else if (peer->len + 1 < sizeof peer->buf) {
            peer->buf[peer->len++] = c;
        } else {
            peer->overlong = 1;
        }
    }
    return peer->link ? 0 : -1;
}

static void send_text(struct line_peer *peer, const char *text)
{
    char err[512];
    if (peer->link &&
        uwb_link_write_all(peer->link, text, strlen(text), WRITE_TIMEOUT_MS, err, sizeof err) != 0) {
        fprintf(stderr, "uwbemu: %s\n", err);
        uwb_link_close(peer->link);
        peer->link = NULL;
    }
}

static void gpio_line(struct emu_board *b, struct line_peer *peer, const char *line)
{
    char reply[256];
    emu_gpio_line(b, line, reply, sizeof reply);
    if (reply[0])
        send_text(peer, reply);
}

static void control_line(struct emu_board *b, struct line_peer *peer, const char *line)
{
    char *reply = emu_control_command(b, line);
    if (!reply) {
        send_text(peer, "{\"class\":\"ERROR\",\"message\":\"out of memory\"}\n");
        return;
    }
    send_text(peer, reply);
    send_text(peer, "\n");
    free(reply);
}

/* uwbemu --ctl ENDPOINT COMMAND */
static int control_client(const char *endpoint, const char *command)
{
    struct uwb_link *link;
    char err[512];
    if (uwb_link_open(endpoint, &link, err, sizeof err) != UWB_LINK_OK) {
        fprintf(stderr, "uwbemu --ctl: %s\n", err);
        return 1;
    }
    if (uwb_link_write_all(link, command, strlen(command), WRITE_TIMEOUT_MS, err, sizeof err) !=
            UWB_LINK_OK ||
        uwb_link_write_all(link, "\n", 1, WRITE_TIMEOUT_MS, err, sizeof err) != UWB_LINK_OK) {
        fprintf(stderr, "uwbemu --ctl: %s\n", err);
        uwb_link_close(link);
        return 1;
    }
    size_t cap = 65536, len = 0;
    char *reply = malloc(cap);
    int rc = 1;
    while (reply) {
        if (len + 1 >= cap) {
            char *bigger = realloc(reply, cap * 2);
            if (!bigger)
                break;
            reply = bigger;
            cap *= 2;
        }
        ssize_t n = uwb_link_read(link, reply + len, cap - len - 1, CTL_TIMEOUT_MS, err, sizeof err);
        if (n < 0) {
            fprintf(stderr, "uwbemu --ctl: %s\n", err);
            break;
        }
        len += (size_t)n;
        reply[len] = '\0';
        char *nl = strchr(reply, '\n');
        if (nl) {
            *nl = '\0';
            puts(reply);
            rc = strstr(reply, "\"class\":\"ERROR\"") ? 1 : 0;
            break;
        }
    }
    free(reply);
    uwb_link_close(link);
    return rc;
}

struct options {
    const char *gpio, *digitiser, *control, *site_io;
    double start_mm, steps_per_mm, home_y_mm;
    int invert_dir, verbose;
    unsigned long long seed;
};

static int parse_number(const char *opt, const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (!*text || *end || errno) {
        fprintf(stderr, "uwbemu: %s: '%s' is not a number\n", opt, text);
        return -1;
    }
    return 0;
}

/* Exit status for usage errors, as uwbd's (sysexits EX_USAGE). */
#define EXIT_USAGE 64

static int parse_args(int argc, char **argv, struct options *o, struct sim_scene *scene)
{
    char err[512];
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = 1;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        } else if (strcmp(a, "--invert-dir") == 0) {
            o->invert_dir = 1;
            takes = 0;
        } else if (strcmp(a, "-v") == 0 || strcmp(a, "--verbose") == 0) {
            o->verbose = 1;
            takes = 0;
        } else if (!v) {
            fprintf(stderr, "uwbemu: %s needs a value (see --help)\n", a);
            return -1;
        } else if (strcmp(a, "--gpio") == 0) {
            o->gpio = v;
        } else if (strcmp(a, "--digitiser") == 0) {
            o->digitiser = v;
        } else if (strcmp(a, "--control") == 0) {
            o->control = v;
        } else if (strcmp(a, "--site-io") == 0) {
            o->site_io = v;
        } else if (strcmp(a, "--scene") == 0) {
            if (sim_scene_load_json(v, scene, err, sizeof err) != 0) {
                fprintf(stderr, "uwbemu: --scene: %s\n", err);
                return -1;
            }
        } else if (strcmp(a, "--set") == 0) {
            const char *eq = strchr(v, '=');
            char key[128];
            if (!eq || eq == v || (size_t)(eq - v) >= sizeof key) {
                fprintf(stderr, "uwbemu: --set '%s': expected KEY=VALUE\n", v);
                return -1;
            }
            snprintf(key, sizeof key, "%.*s", (int)(eq - v), v);
            if (sim_scene_set(scene, key, eq + 1, err, sizeof err) != 0) {
                fprintf(stderr, "uwbemu: --set: %s\n", err);
                return -1;
            }
        } else if (strcmp(a, "--seed") == 0) {
            char *end;
            errno = 0;
            o->seed = strtoull(v, &end, 10);
            if (!*v || *end || errno || v[0] == '-') {
                fprintf(stderr, "uwbemu: --seed: '%s' is not a whole number\n", v);
                return -1;
            }
        } else if (strcmp(a, "--steps-per-mm") == 0) {
            if (parse_number(a, v, &o->steps_per_mm) != 0)
                return -1;
            if (!(o->steps_per_mm > 0)) {
                fprintf(stderr, "uwbemu: --steps-per-mm must be above 0\n");
                return -1;
            }
        } else if (strcmp(a, "--home-y-mm") == 0) {
            if (parse_number(a, v, &o->home_y_mm) != 0)
                return -1;
        } else if (strcmp(a, "--start-mm") == 0) {
            if (parse_number(a, v, &o->start_mm) != 0)
                return -1;
        } else {
            fprintf(stderr, "uwbemu: unknown option '%s' (see --help)\n", a);
            return -1;
        }
        i += takes;
    }
    if (!o->gpio || !o->digitiser) {
        fprintf(stderr, "uwbemu: --gpio and --digitiser are required (see --help)\n");
        return -1;
    }
    return 0;
}

static int listen_on(const char *endpoint, const char *what, struct uwb_link_listener **l)
{
    char err[512];
    if (!endpoint) {
        *l = NULL;
        return 0;
    }
    if (uwb_link_listen(endpoint, l, err, sizeof err) != UWB_LINK_OK) {
        fprintf(stderr, "uwbemu: --%s: %s\n", what, err);
        return -1;
    }
    return 0;
}

static struct uwb_link *accept_one(struct uwb_link_listener *l, const char *what)
{
    struct uwb_link *link;
    char err[512];
    if (uwb_link_accept(l, &link, 0, err, sizeof err) != UWB_LINK_OK) {
        fprintf(stderr, "uwbemu: %s: %s\n", what, err);
        return NULL;
    }
    return link;
}

/* A GPIO-protocol listener (--gpio, --site-io): one peer at a time, a new
 * connection replacing the old one; the lines a peer leaves fall low. */
struct gpio_port {
    struct uwb_link_listener *listener;
    struct line_peer peer;
    unsigned lines;
    const char *what;
};

static void gpio_port_accept(struct emu_board *b, struct gpio_port *port)
{
    struct uwb_link *link = accept_one(port->listener, port->what);
    if (!link)
        return;
    if (port->peer.link) {
        uwb_link_close(port->peer.link);
        emu_gpio_released(b, port->lines);
    }
    port->peer = (struct line_peer){.link = link};
    fprintf(stderr, "uwbemu: %s peer connected\n", port->what);
}

static void gpio_port_readable(struct emu_board *b, struct gpio_port *port)
{
    if (port->peer.link && read_lines(b, &port->peer, gpio_line, port->what) < 0) {
        emu_gpio_released(b, port->lines);
        fprintf(stderr, "uwbemu: %s peer left\n", port->what);
    }
}

static int run(struct emu_board *b, struct uwb_link_listener *gpio_l, struct uwb_link_listener *dig_l,
               struct uwb_link_listener *ctl_l, struct uwb_link_listener *site_l)
{
    struct gpio_port gpio = {.listener = gpio_l, .lines = UWB_GPIO_RIG_LINES, .what = "gpio"};
    struct gpio_port site = {.listener = site_l, .lines = EMU_SITE_LINES, .what = "site-io"};
    struct line_peer control[MAX_CONTROL_CLIENTS];
    memset(control, 0, sizeof control);
    while (!stop_signal && !b->quit) {
        struct pollfd fds[7 + MAX_CONTROL_CLIENTS];
        int nfds = 0;
        fds[nfds++] = (struct pollfd){.fd = uwb_link_listener_fd(gpio_l), .events = POLLIN};
        fds[nfds++] = (struct pollfd){.fd = uwb_link_listener_fd(dig_l), .events = POLLIN};
        fds[nfds++] = (struct pollfd){.fd = ctl_l ? uwb_link_listener_fd(ctl_l) : -1, .events = POLLIN};
        fds[nfds++] =
            (struct pollfd){.fd = gpio.peer.link ? uwb_link_fd(gpio.peer.link) : -1, .events = POLLIN};
        fds[nfds++] = (struct pollfd){.fd = b->digitiser ? uwb_link_fd(b->digitiser) : -1, .events = POLLIN};
        for (int i = 0; i < MAX_CONTROL_CLIENTS; i++)
            fds[nfds++] =
                (struct pollfd){.fd = control[i].link ? uwb_link_fd(control[i].link) : -1, .events = POLLIN};
        fds[nfds++] = (struct pollfd){.fd = site_l ? uwb_link_listener_fd(site_l) : -1, .events = POLLIN};
        fds[nfds++] =
            (struct pollfd){.fd = site.peer.link ? uwb_link_fd(site.peer.link) : -1, .events = POLLIN};
        int n = poll(fds, (nfds_t)nfds, -1);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            perror("uwbemu: poll");
            return 1;
        }
        if (fds[0].revents)
            gpio_port_accept(b, &gpio);
        if (fds[1].revents) {
            struct uwb_link *link = accept_one(dig_l, "digitiser");
            if (link) {
                emu_digitiser_attach(b, link);
                fprintf(stderr, "uwbemu: digitiser peer connected\n");
            }
        }
        if (fds[2].revents) {
            struct uwb_link *link = accept_one(ctl_l, "control");
            int slot = -1;
            for (int i = 0; link && i < MAX_CONTROL_CLIENTS && slot < 0; i++)
                if (!control[i].link)
                    slot = i;
            if (slot >= 0)
                control[slot] = (struct line_peer){.link = link};
            else if (link)
                uwb_link_close(link); /* too many at once: refuse by closing */
        }
        if (fds[3].revents)
            gpio_port_readable(b, &gpio);
        if (fds[4].revents && b->digitiser && emu_digitiser_readable(b) < 0)
            fprintf(stderr, "uwbemu: digitiser peer left\n");
        for (int i = 0; i < MAX_CONTROL_CLIENTS; i++)
            if (fds[5 + i].revents && control[i].link)
                read_lines(b, &control[i], control_line, "control");
        if (fds[5 + MAX_CONTROL_CLIENTS].revents)
            gpio_port_accept(b, &site);
        if (fds[6 + MAX_CONTROL_CLIENTS].revents)
            gpio_port_readable(b, &site);
    }
    if (gpio.peer.link)
        uwb_link_close(gpio.peer.link);
    if (site.peer.link)
        uwb_link_close(site.peer.link);
    for (int i = 0; i < MAX_CONTROL_CLIENTS; i++)
        if (control[i].link)
            uwb_link_close(control[i].link);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "--ctl") == 0) {
        if (argc != 4) {
            fprintf(stderr, "usage: uwbemu --ctl ENDPOINT 'COMMAND'\n");
            return EXIT_USAGE;
        }
        return control_client(argv[2], argv[3]);
    }
    struct sim_scene scene;
    if (sim_scene_default(&scene) != 0) {
        fprintf(stderr, "uwbemu: the simulator's parameter table is broken\n");
        return 70;
    }
    struct options o = {.steps_per_mm = 100, .home_y_mm = -20, .start_mm = 50, .seed = 1};
    if (parse_args(argc, argv, &o, &scene) != 0)
        return EXIT_USAGE;

    struct emu_board board;
    char err[512];
    if (emu_board_init(&board, &scene, o.seed, err, sizeof err) != 0) {
        fprintf(stderr, "uwbemu: scene: %s\n", err);
        emu_board_free(&board);
        return EXIT_USAGE;
    }
    board.steps_per_mm = o.steps_per_mm;
    board.home_y_mm = o.home_y_mm;
    board.invert_dir = o.invert_dir;
    board.verbose = o.verbose;
    board.steps = (long)(o.start_mm * o.steps_per_mm + (o.start_mm >= 0 ? 0.5 : -0.5));

    struct uwb_link_listener *gpio_l = NULL, *dig_l = NULL, *ctl_l = NULL, *site_l = NULL;
    int rc = 1;
    if (listen_on(o.gpio, "gpio", &gpio_l) == 0 && listen_on(o.digitiser, "digitiser", &dig_l) == 0 &&
        listen_on(o.control, "control", &ctl_l) == 0 && listen_on(o.site_io, "site-io", &site_l) == 0) {
        struct sigaction sa = {.sa_handler = on_signal};
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        signal(SIGPIPE, SIG_IGN);
        fprintf(stderr, "uwbemu: listening: gpio %s, digitiser %s%s%s; carriage at %.2f mm above home\n",
                o.gpio, o.digitiser, o.control ? ", control " : "", o.control ? o.control : "", o.start_mm);
        rc = run(&board, gpio_l, dig_l, ctl_l, site_l);
    }
    uwb_link_listener_close(gpio_l);
    uwb_link_listener_close(dig_l);
    uwb_link_listener_close(ctl_l);
    uwb_link_listener_close(site_l);
    emu_board_free(&board);
    return rc;
}
