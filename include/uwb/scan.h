/* A recorded scan in memory, and the uwbscan/1 file that carries it.
 * Everything downstream (imaging, outputs) sees only struct uwb_scan; the
 * appliance's acquisition fills one, --replay reads one from disk. */
#ifndef UWB_SCAN_H
#define UWB_SCAN_H

#include <stddef.h>

#define UWBSCAN_FORMAT "uwbscan/1"
#define UWBSCAN_MAX_POSITIONS 4096
#define UWBSCAN_MAX_SAMPLES 1048576
#define UWBSCAN_MAX_HEADER_BYTES (1024u * 1024u)

struct uwb_scan {
    int positions;              /* K traces */
    int samples;                /* S samples per trace */
    double sample_interval_s;
    double t0_s;                /* time of sample 0 after the pulse leaves Tx */
    double *antenna_y_m;        /* K reference-point heights */
    double tx_m[2];             /* Tx phase centre [dy, dz] from reference */
    double rx_m[2];             /* Rx phase centre [dy, dz] from reference */
    double eps_r;               /* 1.0 when the file has none */
    int has_target_z;
    double target_z_m[2];       /* [near, far] expected face range */
    int stack;                  /* 0 when absent */
    char *created;              /* optional strings: NULL when absent */
    char *scan_id;
    char *source;
    char *comment;
    char *extra_json;           /* unknown header keys as a JSON object text, kept for rewrite; NULL if none */
    float *data;                /* K*S samples, position-major: data[k*S + s] */
};

/* Allocate antenna_y_m and data for a K x S scan and zero every other field
 * (eps_r = 1). Returns 0, or -1 with err filled. */
int uwb_scan_alloc(struct uwb_scan *scan, int positions, int samples, char *err, size_t errlen);
void uwb_scan_free(struct uwb_scan *scan);
/* Deep copy (for tools that modify a scan). */
int uwb_scan_copy(struct uwb_scan *dst, const struct uwb_scan *src, char *err, size_t errlen);

/* Parse a whole uwbscan/1 image held in memory. `name` is used in messages
 * ("NAME: problem"). On failure *scan is left freed/zeroed. */
int uwbscan_parse(const void *buf, size_t len, const char *name,
                  struct uwb_scan *scan, char *err, size_t errlen);
int uwbscan_read_file(const char *path, struct uwb_scan *scan, char *err, size_t errlen);

/* Serialise to a malloc'd buffer (caller frees). */
int uwbscan_serialise(const struct uwb_scan *scan, unsigned char **buf, size_t *len,
                      char *err, size_t errlen);
/* Write atomically (temp + fsync + rename): the old file, if any, survives a failure. */
int uwbscan_write_file(const char *path, const struct uwb_scan *scan, char *err, size_t errlen);

#endif
