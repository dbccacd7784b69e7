/* A recorded scan in memory, and the uwbscan/1 file that carries it.
 * Everything downstream (imaging, outputs) sees only struct uwb_scan; the
 * appliance's acquisition fills one, --replay reads one from disk. */
#ifndef UWB_SCAN_H
#define UWB_SCAN_H

#include <stddef.h>

#define UWBSCAN_FORMAT "uwbscan/1"
#define UWBSCAN_MAX_POSITIONS 4096
#define UWBSCAN_MAX_SAMPLES 1048576
#define UWBSCAN_MAX_HEADER_BYTES ((size_t)1024 * 1024)
/* positions x samples at most: 64 MiB of float32, so that reading and
 * replaying one is bounded (README "What the reader refuses": a replay at
 * the limit peaks under 400 MiB). The biggest scan this rig makes (650 mm
 * at 1 mm steps, 4096 samples) is 2.7 Mi samples. */
#define UWBSCAN_MAX_SAMPLE_MIB 64
#define UWBSCAN_MAX_SAMPLE_COUNT ((size_t)UWBSCAN_MAX_SAMPLE_MIB * 1024 * 1024 / sizeof(float))

/* What this rig can record, so that every accepted scan is bounded work
 * (the imaging grids scale with travel / step and range / pixel):
 * - antenna_y_m strictly increasing, neighbours at least 1 mm apart: the
 *   carriage's backlash alone is 0.5 mm, and a step finer than the 1 mm
 *   image pixel adds nothing (the method uses 30 mm);
 * - travel (last - first) at most 5 m: the tallest power-transformer
 *   windings are about 3 m (4096 positions 1 mm apart still fit);
 * - sample_interval_s from 0.1 ps to 1 ns (a 1-3 GHz pulse needs samples
 *   under 0.17 ns), t0_s within 1 us of the pulse (150 m of range in air);
 * - tx/rx offsets within 1 m of the reference point, eps_r at most 100
 *   (oil is 2.2, water 80), target_z_m within 0..10 m of the antennas. */
#define UWBSCAN_MIN_STEP_M 0.001
#define UWBSCAN_MAX_TRAVEL_M 5.0
#define UWBSCAN_MIN_SAMPLE_INTERVAL_S 1e-13
#define UWBSCAN_MAX_SAMPLE_INTERVAL_S 1e-9
#define UWBSCAN_MAX_ABS_T0_S 1e-6
#define UWBSCAN_MAX_ANTENNA_OFFSET_M 1.0
#define UWBSCAN_MAX_EPS_R 100.0
#define UWBSCAN_MAX_RANGE_M 10.0

struct uwb_scan {
    int positions; /* K traces */
    int samples;   /* S samples per trace */
    double sample_interval_s;
    double t0_s;         /* time of sample 0 after the pulse leaves Tx */
    double *antenna_y_m; /* K reference-point heights */
    double tx_m[2];      /* Tx phase centre [dy, dz] from reference */
    double rx_m[2];      /* Rx phase centre [dy, dz] from reference */
    double eps_r;        /* 1.0 when the file has none */
    int has_target_z;
    double target_z_m[2]; /* [near, far] expected face range */
    int stack;            /* 0 when absent */
    char *created;        /* optional strings: NULL when absent */
    char *scan_id;
    char *source;
    char *comment;
    char *extra_json; /* unknown header keys as a JSON object text, kept for rewrite; NULL if none */
    float *data;      /* K*S samples, position-major: data[k*S + s] */
};

/* Allocate antenna_y_m and data for a K x S scan and zero every other field
 * (eps_r = 1). Returns 0, or -1 with err filled. */
int uwb_scan_alloc(struct uwb_scan *scan, int positions, int samples, char *err, size_t errlen);
void uwb_scan_free(struct uwb_scan *scan);
/* Deep copy (for tools that modify a scan). */
int uwb_scan_copy(struct uwb_scan *dst, const struct uwb_scan *src, char *err, size_t errlen);

/* Parse a whole uwbscan/1 image held in memory. `name` is used in messages
 * ("NAME: problem"). On failure *scan is left freed/zeroed. */
int uwbscan_parse(const void *buf, size_t len, const char *name, struct uwb_scan *scan, char *err,
                  size_t errlen);
int uwbscan_read_file(const char *path, struct uwb_scan *scan, char *err, size_t errlen);

/* Serialise to a malloc'd buffer (caller frees). */
int uwbscan_serialise(const struct uwb_scan *scan, unsigned char **buf, size_t *len, char *err,
                      size_t errlen);
/* Write atomically (temp + fsync + rename): the old file, if any, survives a failure. */
int uwbscan_write_file(const char *path, const struct uwb_scan *scan, char *err, size_t errlen);

#endif
