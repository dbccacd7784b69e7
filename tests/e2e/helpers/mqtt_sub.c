/* mqtt_sub PORT USER PASSWORD TOPIC COUNT TIMEOUT_S: subscribes on the
 * broker at 127.0.0.1:PORT (QoS 1) and prints COUNT messages, one line
 * each, "TOPIC RETAINED PAYLOAD" (RETAINED 1 or 0), flushing each, then
 * exits 0; exits 1 when they have not all come within TIMEOUT_S. It keeps
 * trying to connect until then, so it may start before the broker. For
 * the e2e tests: a fresh Debian minbase has no mosquitto_sub. Says
 * "mqtt_sub: subscribed" on stderr once the broker has granted it. */
#include <mosquitto.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int wanted, received;
static const char *topic;

static void on_connect(struct mosquitto *mosq, void *ctx, int rc)
{
    (void)ctx;
    if (rc == 0)
        mosquitto_subscribe(mosq, NULL, topic, 1);
}

static void on_subscribe(struct mosquitto *mosq, void *ctx, int mid, int qos_count, const int *granted)
{
    (void)mosq;
    (void)ctx;
    (void)mid;
    (void)qos_count;
    (void)granted;
    fprintf(stderr, "mqtt_sub: subscribed\n");
}

static void on_message(struct mosquitto *mosq, void *ctx, const struct mosquitto_message *msg)
{
    (void)mosq;
    (void)ctx;
    if (received >= wanted)
        return;
    printf("%s %d %.*s\n", msg->topic, msg->retain ? 1 : 0, msg->payloadlen, (const char *)msg->payload);
    fflush(stdout);
    received++;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

int main(int argc, char **argv)
{
    if (argc != 7) {
        fprintf(stderr, "usage: mqtt_sub PORT USER PASSWORD TOPIC COUNT TIMEOUT_S\n");
        return 2;
    }
    int port = atoi(argv[1]);
    topic = argv[4];
    wanted = atoi(argv[5]);
    double deadline = now_s() + atof(argv[6]);
    mosquitto_lib_init();
    struct mosquitto *mosq = mosquitto_new(NULL, true, NULL);
    if (!mosq)
        return 2;
    mosquitto_username_pw_set(mosq, argv[2], argv[3]);
    mosquitto_connect_callback_set(mosq, on_connect);
    mosquitto_message_callback_set(mosq, on_message);
    mosquitto_subscribe_callback_set(mosq, on_subscribe);
    int connected = 0;
    while (received < wanted && now_s() < deadline) {
        if (!connected) {
            connected = mosquitto_connect(mosq, "127.0.0.1", port, 30) == MOSQ_ERR_SUCCESS;
            if (!connected) {
                nanosleep(&(struct timespec){.tv_nsec = 50000000L}, NULL);
                continue;
            }
        }
        if (mosquitto_loop(mosq, 100, 1) != MOSQ_ERR_SUCCESS) {
            connected = 0;
            nanosleep(&(struct timespec){.tv_nsec = 50000000L}, NULL);
        }
    }
    mosquitto_disconnect(mosq);
    mosquitto_destroy(mosq);
    mosquitto_lib_cleanup();
    if (received < wanted) {
        fprintf(stderr, "mqtt_sub: %d of %d messages on %s within %s s\n", received, wanted, topic, argv[6]);
        return 1;
    }
    return 0;
}
