/* mqtt_pub PORT USER PASSWORD TOPIC MESSAGE: publishes MESSAGE on TOPIC at
 * the broker on 127.0.0.1:PORT, QoS 1, not retained, and exits 0 once the
 * broker has acknowledged it; 1 if that has not happened within 10 s. For
 * the e2e tests: a fresh Debian minbase has no mosquitto_pub. */
#include <mosquitto.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int acked;

static void on_publish(struct mosquitto *mosq, void *ctx, int mid)
{
    (void)mosq;
    (void)ctx;
    (void)mid;
    acked = 1;
}

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: mqtt_pub PORT USER PASSWORD TOPIC MESSAGE\n");
        return 2;
    }
    mosquitto_lib_init();
    struct mosquitto *mosq = mosquitto_new(NULL, true, NULL);
    if (!mosq)
        return 2;
    mosquitto_username_pw_set(mosq, argv[2], argv[3]);
    mosquitto_publish_callback_set(mosq, on_publish);
    int rc = mosquitto_connect(mosq, "127.0.0.1", atoi(argv[1]), 30);
    if (rc == MOSQ_ERR_SUCCESS)
        rc = mosquitto_publish(mosq, NULL, argv[4], (int)strlen(argv[5]), argv[5], 1, false);
    struct timespec start, now;
    clock_gettime(CLOCK_MONOTONIC, &start);
    while (rc == MOSQ_ERR_SUCCESS && !acked) {
        rc = mosquitto_loop(mosq, 100, 1);
        clock_gettime(CLOCK_MONOTONIC, &now);
        if (now.tv_sec - start.tv_sec > 10)
            break;
    }
    mosquitto_disconnect(mosq);
    mosquitto_destroy(mosq);
    mosquitto_lib_cleanup();
    if (!acked)
        fprintf(stderr, "mqtt_pub: %s not acknowledged (%s)\n", argv[4], mosquitto_strerror(rc));
    return acked ? 0 : 1;
}
