/* modbus_client: a libmodbus master for the e2e scripts, reading uwbd's
 * register map and writing its coils, over RTU (a unix socket that uwbd
 * connects to: libserialport cannot open ptys) or Modbus TCP.
 *
 *   modbus_client freeport                 a free TCP port on 127.0.0.1
 *   modbus_client rtu-listen PATH UNIT CMD...   listen on unix PATH, take
 *                                          uwbd's connection (30 s at most)
 *   modbus_client tcp HOST PORT CMD...     connect to uwbd's Modbus TCP
 * CMD, in order:
 *   dump           one line: status=.. displacement=.. sigma=.. height_change=..
 *                  lower_edge=.. upper_edge=.. scan_count=.. scan_time=.. health=..
 *                  contacts=.. version=.. (0.01 mm as integers; "none" for 0x8000
 *                  and 0x80000000); the holding registers must equal the input ones
 *   wait-count=N   read until the scan counter is >= N (120 s at most)
 *   coil=A:V       write coil A (0/1): "coil A=V: ok" or the error
 *   coils          "coils=B0B1..." read back
 *   write-register try to write holding register 0: "write-register: ok" or the error
 *   unit=N         talk to unit N from now on
 *   probe          read one register: "probe: ok" or the error
 * Exit 0; 1 no connection, a timeout of wait-count or a dump that failed; 2 usage. */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <modbus/modbus.h>

#include "integrations/modbus_registers.h"

static int usage(void)
{
    fprintf(stderr, "usage: modbus_client freeport | rtu-listen PATH UNIT CMD... | tcp HOST PORT CMD...\n");
    return 2;
}

static int free_port(void)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t len = sizeof a;
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) != 0 ||
        getsockname(fd, (struct sockaddr *)&a, &len) != 0) {
        perror("modbus_client: freeport");
        return 1;
    }
    printf("%d\n", ntohs(a.sin_port));
    close(fd);
    return 0;
}

/* Listens on PATH and returns the first connection, or -1. */
static int accept_unix(const char *path)
{
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
    unlink(path);
    int l = socket(AF_UNIX, SOCK_STREAM, 0);
    if (l < 0 || bind(l, (struct sockaddr *)&a, sizeof a) != 0 || listen(l, 1) != 0) {
        fprintf(stderr, "modbus_client: listen on %s: %s\n", path, strerror(errno));
        return -1;
    }
    struct pollfd p = {.fd = l, .events = POLLIN};
    int fd = poll(&p, 1, 30000) == 1 ? accept(l, NULL, NULL) : -1;
    if (fd < 0)
        fprintf(stderr, "modbus_client: nobody connected to %s within 30 s\n", path);
    close(l);
    unlink(path);
    return fd;
}

static void print16(const char *name, uint16_t v)
{
    if (v == UWBD_MODBUS_NONE16)
        printf(" %s=none", name);
    else
        printf(" %s=%d", name, (int16_t)v);
}

static void print32(const char *name, const uint16_t *r, int is_signed)
{
    uint32_t v = ((uint32_t)r[0] << 16) | r[1];
    if (is_signed && v == UWBD_MODBUS_NONE32)
        printf(" %s=none", name);
    else if (is_signed)
        printf(" %s=%ld", name, (long)(int32_t)v);
    else
        printf(" %s=%lu", name, (unsigned long)v);
}

static int read_map(modbus_t *ctx, uint16_t *in)
{
    if (modbus_read_input_registers(ctx, 0, UWBD_MODBUS_REGISTER_COUNT, in) != UWBD_MODBUS_REGISTER_COUNT) {
        fprintf(stderr, "modbus_client: reading the input registers: %s\n", modbus_strerror(errno));
        return -1;
    }
    return 0;
}

static int dump(modbus_t *ctx)
{
    uint16_t in[UWBD_MODBUS_REGISTER_COUNT], hold[UWBD_MODBUS_REGISTER_COUNT];
    if (read_map(ctx, in) != 0)
        return -1;
    if (modbus_read_registers(ctx, 0, UWBD_MODBUS_REGISTER_COUNT, hold) != UWBD_MODBUS_REGISTER_COUNT) {
        fprintf(stderr, "modbus_client: reading the holding registers: %s\n", modbus_strerror(errno));
        return -1;
    }
    /* The counter or the health bits may move between the two reads only
     * if a scan ends in between; the scripts dump when none runs. */
    if (memcmp(in, hold, sizeof in) != 0) {
        fprintf(stderr, "modbus_client: the holding registers differ from the input registers\n");
        return -1;
    }
    printf("status=%u", in[UWBD_MODBUS_REG_STATUS]);
    print16("displacement", in[UWBD_MODBUS_REG_DISPLACEMENT]);
    print16("sigma", in[UWBD_MODBUS_REG_SIGMA]);
    print16("height_change", in[UWBD_MODBUS_REG_HEIGHT_CHANGE]);
    print32("lower_edge", &in[UWBD_MODBUS_REG_LOWER_EDGE], 1);
    print32("upper_edge", &in[UWBD_MODBUS_REG_UPPER_EDGE], 1);
    print32("scan_count", &in[UWBD_MODBUS_REG_SCAN_COUNT], 0);
    print32("scan_time", &in[UWBD_MODBUS_REG_SCAN_TIME], 0);
    printf(" health=%u contacts=%u version=%u", in[UWBD_MODBUS_REG_HEALTH], in[UWBD_MODBUS_REG_CONTACTS],
           in[UWBD_MODBUS_REG_MAP_VERSION]);
    printf(" radial_status=%u", in[UWBD_MODBUS_REG_RADIAL_STATUS]);
    print16("radial_change", in[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    print16("radial_sigma", in[UWBD_MODBUS_REG_RADIAL_SIGMA]);
    print32("radial_at", &in[UWBD_MODBUS_REG_RADIAL_AT], 1);
    print16("radial_tilt", in[UWBD_MODBUS_REG_RADIAL_TILT]);
    print16("radial_tilt_sigma", in[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA]);
    printf("\n");
    return 0;
}

static int wait_count(modbus_t *ctx, unsigned long want)
{
    struct timespec tenth = {.tv_sec = 0, .tv_nsec = 100000000L};
    for (int i = 0; i < 1200; i++) {
        uint16_t in[UWBD_MODBUS_REGISTER_COUNT];
        if (read_map(ctx, in) == 0 && (((unsigned long)in[UWBD_MODBUS_REG_SCAN_COUNT] << 16) |
                                       in[UWBD_MODBUS_REG_SCAN_COUNT + 1]) >= want)
            return 0;
        nanosleep(&tenth, NULL);
    }
    fprintf(stderr, "modbus_client: the scan counter did not reach %lu within 120 s\n", want);
    return -1;
}

static int run(modbus_t *ctx, int argc, char **argv)
{
    for (int i = 0; i < argc; i++) {
        const char *c = argv[i];
        int a, v;
        if (strcmp(c, "dump") == 0) {
            if (dump(ctx) != 0)
                return 1;
        } else if (strncmp(c, "wait-count=", 11) == 0) {
            if (wait_count(ctx, strtoul(c + 11, NULL, 10)) != 0)
                return 1;
        } else if (sscanf(c, "coil=%d:%d", &a, &v) == 2) {
            int rc = modbus_write_bit(ctx, a, v);
            printf("coil %d=%d: %s\n", a, v, rc == 1 ? "ok" : modbus_strerror(errno));
        } else if (strcmp(c, "coils") == 0) {
            uint8_t bits[UWBD_MODBUS_COIL_COUNT];
            if (modbus_read_bits(ctx, 0, UWBD_MODBUS_COIL_COUNT, bits) != UWBD_MODBUS_COIL_COUNT) {
                printf("coils: %s\n", modbus_strerror(errno));
                continue;
            }
            printf("coils=");
            for (int b = 0; b < UWBD_MODBUS_COIL_COUNT; b++)
                printf("%u", bits[b]);
            printf("\n");
        } else if (strcmp(c, "write-register") == 0) {
            int rc = modbus_write_register(ctx, 0, 1);
            printf("write-register: %s\n", rc == 1 ? "ok" : modbus_strerror(errno));
        } else if (sscanf(c, "unit=%d", &a) == 1) {
            modbus_set_slave(ctx, a);
        } else if (strcmp(c, "probe") == 0) {
            uint16_t r;
            int rc = modbus_read_input_registers(ctx, 0, 1, &r);
            printf("probe: %s\n", rc == 1 ? "ok" : modbus_strerror(errno));
        } else {
            fprintf(stderr, "modbus_client: unknown command '%s'\n", c);
            return 2;
        }
        fflush(stdout);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "freeport") == 0)
        return free_port();
    if (argc < 4)
        return usage();
    modbus_t *ctx;
    int fd = -1;
    if (strcmp(argv[1], "rtu-listen") == 0) {
        fd = accept_unix(argv[2]);
        if (fd < 0)
            return 1;
        ctx = modbus_new_rtu("/dev/null", 115200, 'N', 8, 1); /* never connected: the socket is set */
        if (!ctx)
            return 1;
        modbus_set_socket(ctx, fd);
        modbus_set_slave(ctx, atoi(argv[3]));
    } else if (strcmp(argv[1], "tcp") == 0) {
        ctx = modbus_new_tcp_pi(argv[2], argv[3]);
        if (!ctx || modbus_connect(ctx) != 0) {
            fprintf(stderr, "modbus_client: connect to %s:%s: %s\n", argv[2], argv[3],
                    modbus_strerror(errno));
            return 1;
        }
    } else {
        return usage();
    }
    modbus_set_response_timeout(ctx, 2, 0);
    int rc = run(ctx, argc - 4, argv + 4);
    if (fd >= 0) {
        modbus_set_socket(ctx, -1);
        close(fd);
    } else {
        modbus_close(ctx);
    }
    modbus_free(ctx);
    return rc;
}
