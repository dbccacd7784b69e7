/* uwbimpair: write a noisy copy of a uwbscan/1 file (seeded). */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "impair/impair.h"
#include "uwb/scan.h"

static const char usage[] =
    "usage: uwbimpair [options] IN.uwbscan OUT.uwbscan\n"
    "\n"
    "Writes a copy of IN with white noise, per-position timing jitter and amplitude drift\n"
    "along the aperture. The same seed and options give the same file, byte for byte.\n"
    "\n"
    "  --seed N            seed of the random stream (unsigned 64-bit; default 1)\n"
    "  --snr-db DB         white Gaussian noise, rms DB below the reference peak (default: none)\n"
    "  --jitter-ps PS      each position's trace delayed by PS * N(0,1) picoseconds (default 0)\n"
    "  --drift-linear F    gain 1 + F*k/(K-1) at position k of K: F from first to last (default 0)\n"
    "  --drift-random F    plus F * N(0,1) per position (default 0)\n"
    "  -h, --help          this text\n"
    "\n"
    "The reference peak is the largest |sample| over every position from the start of the\n"
    "echoes after the direct coupling: the two-way delay (the header's Tx/Rx offsets and\n"
    "eps_r) to a point 0.1 m straight ahead of the antenna reference point, plus two periods\n"
    "of the scan's dominant frequency (the peak of its mean power spectrum). It is measured\n"
    "before any impairment. Draw order: for each position, its jitter normal then its drift\n"
    "normal; then the noise, position by position, sample by sample. Every draw is made\n"
    "whatever the options, so a seed's noise is the same with or without jitter and drift.\n"
    "Normals: xoshiro256** seeded through splitmix64, Box-Muller (pairs). The trace is\n"
    "delayed (zero-padded FFT phase ramp), then scaled, then the noise is added. The header\n"
    "is kept; its comment records what was applied.\n"
    "\n"
    "Exit status: 0 written; 64 bad usage; 65 IN is malformed or unusable; 66 IN cannot be\n"
    "read; 73 OUT cannot be written.\n";

static int parse_double(const char *opt, const char *text, double min, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end || !isfinite(v) || v < min) {
        fprintf(stderr, "uwbimpair: %s: not a number >= %g: '%s'\n", opt, min, text);
        return -1;
    }
    *out = v;
    return 0;
}

int main(int argc, char **argv)
{
    struct uwb_impairment imp = {0};
    imp.seed = 1;
    const char *paths[2] = {NULL, NULL};
    int npaths = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            fputs(usage, stdout);
            return 0;
        }
        if (a[0] == '-' && a[1] == '-') {
            if (i + 1 >= argc) {
                fprintf(stderr, "uwbimpair: %s needs a value\n%s", a, usage);
                return 64;
            }
            const char *v = argv[++i];
            double jitter_ps = 0.0;
            int bad = 0;
            if (!strcmp(a, "--seed")) {
                char *end;
                errno = 0;
                uintmax_t s = strtoumax(v, &end, 10);
                bad = errno || end == v || *end || v[0] == '-' || s > UINT64_MAX;
                if (bad)
                    fprintf(stderr, "uwbimpair: --seed: not an unsigned 64-bit integer: '%s'\n", v);
                imp.seed = (uint64_t)s;
            } else if (!strcmp(a, "--snr-db")) {
                bad = parse_double(a, v, -INFINITY, &imp.snr_db) != 0;
                imp.add_noise = 1;
            } else if (!strcmp(a, "--jitter-ps")) {
                bad = parse_double(a, v, 0.0, &jitter_ps) != 0;
                imp.jitter_s = jitter_ps * 1e-12;
            } else if (!strcmp(a, "--drift-linear")) {
                bad = parse_double(a, v, -INFINITY, &imp.drift_linear) != 0;
            } else if (!strcmp(a, "--drift-random")) {
                bad = parse_double(a, v, 0.0, &imp.drift_random) != 0;
            } else {
                fprintf(stderr, "uwbimpair: unknown option %s\n%s", a, usage);
                return 64;
            }
            if (bad)
                return 64;
            continue;
        }
        if (npaths == 2) {
            fprintf(stderr, "uwbimpair: one input and one output, not '%s' too\n%s", a, usage);
            return 64;
        }
        paths[npaths++] = a;
    }
    if (npaths != 2) {
        fprintf(stderr, "uwbimpair: give IN.uwbscan and OUT.uwbscan\n%s", usage);
        return 64;
    }
    struct uwb_scan scan;
    char err[512];
    FILE *probe = fopen(paths[0], "rb");
    if (!probe) {
        fprintf(stderr, "uwbimpair: %s: cannot open: %s\n", paths[0], strerror(errno));
        return 66;
    }
    fclose(probe);
    if (uwbscan_read_file(paths[0], &scan, err, sizeof err) != 0) {
        fprintf(stderr, "uwbimpair: %s\n", err);
        return 65;
    }
    struct uwb_impairment_report rep;
    if (uwb_impair_scan(&scan, &imp, &rep, err, sizeof err) != 0) {
        fprintf(stderr, "uwbimpair: %s: %s\n", paths[0], err);
        uwb_scan_free(&scan);
        return 65;
    }
    char noise[160] = "no noise";
    if (imp.add_noise)
        snprintf(noise, sizeof noise, "noise %.6g rms, %.6g dB below the peak %.6g from %.4g ns on",
                 rep.noise_sigma, imp.snr_db, rep.reference_peak, rep.gate_s * 1e9);
    char note[768];
    snprintf(note, sizeof note,
             "%.300s%simpaired by uwbimpair: seed %" PRIu64 ", %s, jitter %.6g ps rms, "
             "drift %.6g linear + %.6g rms",
             scan.comment ? scan.comment : "", scan.comment ? "; " : "", imp.seed, noise, imp.jitter_s * 1e12,
             imp.drift_linear, imp.drift_random);
    char *comment = strdup(note);
    if (!comment) {
        fprintf(stderr, "uwbimpair: out of memory\n");
        uwb_scan_free(&scan);
        return 70;
    }
    free(scan.comment);
    scan.comment = comment;
    int rc = uwbscan_write_file(paths[1], &scan, err, sizeof err);
    uwb_scan_free(&scan);
    if (rc != 0) {
        fprintf(stderr, "uwbimpair: %s\n", err);
        return 73;
    }
    return 0;
}
