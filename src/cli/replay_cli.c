/* uwbd --replay: evaluate a recorded scan against a baseline, as the
 * appliance would, and print the verdict line. The work is done by the
 * library (uwb_evaluate in src/evaluate, the one path from a scan to a
 * verdict; src/output for the images). */
#include <errno.h>
#include <getopt.h>
#include <locale.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sysexits.h>
#include <unistd.h>

#include "uwb/atomic_file.h"
#include "uwb/cli.h"
#include "config/winding_span.h"
#include "state/baseline_store.h"
#include "daemon/daemon.h"
#include "uwb/evaluate.h"
#include "uwb/render.h"
#include "uwb/reply_text.h"
#include "uwb/scan.h"
#include "uwb/verdict_json.h"

void uwbd_replay_usage(FILE *f)
{
    fprintf(
        f,
        "usage: uwbd --replay CURRENT.uwbscan [--baseline BASE.uwbscan] [--out DIR] [options]\n"
        "\n"
        "Images a recorded scan, finds the winding's lower and upper edges and, against a\n"
        "baseline scan of the intact winding, reports the axial displacement. Prints one\n"
        "JSON verdict line on stdout: for a scan the appliance archived, with its baseline, the\n"
        "verdict it recorded (the fields only the appliance adds, such as scan_file, aside).\n"
        "\n"
        "  --replay FILE            the scan to evaluate (uwbscan/1)\n"
        "  --baseline FILE          baseline scan (intact winding); without it only edges are reported.\n"
        "                           What the appliance recorded with it is read from the description\n"
        "                           beside it (BASE.json for BASE.uwbscan: the state directory's\n"
        "                           baseline/current.json, or baseline/history/ID.json): its time zero\n"
        "                           (direct coupling), scans averaged and repeatability. Without one, the\n"
        "                           time zero is measured on FILE, as commissioning does\n"
        "  --out DIR                write the PNG images (STEM-migrated, STEM-bscan, STEM-comparison) and\n"
        "                           the verdict line as STEM.json here (STEM: the scan id, else the file "
        "name)\n"
        "  --migration fixed|float  migration arithmetic (default fixed: int16 samples, Q15 weights)\n"
        "  --target-z NEAR:FAR      look for the winding's face only between these ranges, metres\n"
        "                           (default: the scan's target_z_m, else 0.15:1.6)\n"
        "  --winding-span LOW:HIGH  where the drawings put the winding's lower and upper ends, metres in\n"
        "                           the scan's y: a face found elsewhere is another reflector's\n"
        "  --time-zero-offset-ps T  calibration added to the header's t0_s, picoseconds (default 0)\n"
        "  --watch-mm D             |displacement| from which status is watch (default 2)\n"
        "  --alarm-mm D             |displacement| from which status is alarm (default 5)\n"
        "  --max-uncertainty-mm U   above this 1-sigma uncertainty the verdict is inconclusive (default 1)\n"
        "  --edge-fraction F        edge where the face profile crosses F of its peak (default 0.5)\n"
        "  --direct-coupling-window-ns T  look for the direct coupling up to T ns (default 2)\n"
        "  --direct-coupling-tolerance-ps T  against a baseline, a direct coupling moved more than T ps is\n"
        "                           inconclusive, not compared: cable or antenna changed (default 20)\n"
        "  --text                   print the verdict for people (its status, figures, reason and\n"
        "                           images as lines, as uwbd ctl --text does) instead of its JSON line;\n"
        "                           STEM.json in --out is the JSON line still\n"
        "  -h, --help               this text\n"
        "  --version                print the version\n"
        "\n"
        "Exit status: 0 a verdict was produced (status may still be inconclusive); 64 bad usage;\n"
        "65 an input file is malformed; 66 an input file cannot be read; 73 an output cannot be\n"
        "written; 70 internal error. Errors go to stderr, naming the file and the problem.\n");
}

/* The appliance first (the daemon, then ctl to talk to it), the replay of
 * a recorded scan last: the order in which an engineer meets them. */
static void usage(FILE *f)
{
    uwbd_daemon_usage(f);
    fputs("\n", f);
    uwbd_ctl_usage(f);
    fputs("\n", f);
    uwbd_replay_usage(f);
}

static int parse_number(const char *opt, const char *text, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end) {
        fprintf(stderr, "uwbd: %s: '%s' is not a number\n", opt, text);
        return -1;
    }
    *out = v;
    return 0;
}

/* A:B, two finite numbers with A < B (strtod, not sscanf: "5x:6" is no pair). */
static int parse_pair(const char *text, double *a, double *b)
{
    char *colon, *end;
    errno = 0;
    *a = strtod(text, &colon);
    if (errno || colon == text || *colon != ':')
        return -1;
    *b = strtod(colon + 1, &end);
    if (errno || end == colon + 1 || *end != '\0')
        return -1;
    return isfinite(*a) && isfinite(*b) && *b > *a ? 0 : -1;
}

/* --target-z NEAR:FAR, metres, 0 <= NEAR < FAR. */
static int parse_target_z(const char *text, double *near_m, double *far_m)
{
    return parse_pair(text, near_m, far_m) == 0 && *near_m >= 0.0 ? 0 : -1;
}

/* Reads a scan the analysis can take: what the format or the analysis
 * refuses is bad input (65), so that 70 is left to internal faults. */
static int read_scan(const char *path, struct uwb_scan *scan)
{
    char err[512];
    if (uwbscan_read_file(path, scan, err, sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s\n", err);
        return access(path, R_OK) != 0 ? EX_NOINPUT : EX_DATAERR;
    }
    if (uwb_analysis_check_input(scan, err, sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s: %s\n", path, err);
        uwb_scan_free(scan);
        return EX_DATAERR;
    }
    return 0;
}

/* File stem for images: the scan id if it is a safe file name, else the
 * input's base name without its extension. */
static void image_stem(const struct uwb_scan *scan, const char *path, char *stem, size_t n)
{
    const char *src = scan->scan_id;
    if (!src || !*src) {
        src = strrchr(path, '/');
        src = src ? src + 1 : path;
    }
    size_t j = 0;
    for (size_t i = 0; src[i] && j + 1 < n; i++) {
        char c = src[i];
        int safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                   c == '_' || c == '.';
        stem[j++] = safe ? c : '_';
    }
    stem[j] = '\0';
    char *dot = strstr(stem, ".uwbscan");
    if (dot && dot != stem)
        *dot = '\0';
    if (!stem[0] || stem[0] == '.')
        snprintf(stem, n, "scan");
}

enum {
    OPT_REPLAY = 256,
    OPT_BASELINE,
    OPT_OUT,
    OPT_MIGRATION,
    OPT_TARGET_Z,
    OPT_WINDING_SPAN,
    OPT_T0,
    OPT_WATCH,
    OPT_ALARM,
    OPT_MAX_UNC,
    OPT_EDGE_FRACTION,
    OPT_DC_WINDOW,
    OPT_DC_TOLERANCE,
    OPT_TEXT,
    OPT_VERSION
};

/* What the appliance recorded with the baseline: BASE.json beside
 * BASE.uwbscan, when there and describing this scan. Returns 0, or
 * EX_DATAERR when the description is there but unreadable. */
static int baseline_record(const char *path, const struct uwb_scan *scan, struct uwb_baseline_record *rec)
{
    memset(rec, 0, sizeof *rec);
    rec->scan = scan;
    static const char suffix[] = ".uwbscan";
    size_t n = strlen(path), k = sizeof suffix - 1;
    if (n <= k || strcmp(path + n - k, suffix) != 0)
        return 0;
    char info_path[4096];
    snprintf(info_path, sizeof info_path, "%.*s.json", (int)(n - k), path);
    struct uwbd_baseline_info info;
    char err[1024];
    int rc = uwbd_baseline_info_read(info_path, &info, err, sizeof err);
    if (rc == 1)
        return 0;
    if (rc != 0) {
        fprintf(stderr, "uwbd: %s\n", err);
        return EX_DATAERR;
    }
    char id[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id(scan->scan_id ? scan->scan_id : "", id, sizeof id);
    if (strcmp(info.scan_id, id) != 0) { /* the appliance rebuilds such a description from the scan */
        fprintf(stderr,
                "uwbd: warning: %s describes baseline %s, not %s: not used; time zero measured on %s\n",
                info_path, info.scan_id, id, path);
        return 0;
    }
    rec->has_direct_coupling = info.has_direct_coupling;
    rec->direct_coupling_s = info.direct_coupling_s;
    rec->scans = info.scans;
    rec->has_repeatability = info.has_repeatability;
    rec->repeatability_m = info.repeatability_m;
    return 0;
}

/* --out DIR: the verdict line beside the images, as the archive keeps it. */
static int write_verdict_file(const char *dir, const char *stem, const char *json)
{
    char path[4096], err[1024];
    snprintf(path, sizeof path, "%s/%s.json", dir, stem);
    struct atomic_file af;
    if (uwb_atomic_file_open(&af, path, err, sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s\n", err);
        return -1;
    }
    fprintf(af.fp, "%s\n", json);
    if (uwb_atomic_file_commit(&af, err, sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s\n", err);
        return -1;
    }
    return 0;
}

/* A replay is one short run whose analysis allocates and frees image-sized
 * buffers (up to a few MiB) many times over. By default glibc gives each
 * such block its own mmap and returns it on free, so every reuse faults its
 * pages in and zeroes them again: about 4000 extra page faults and 5-9 ms
 * of the replay (make bench). Keeping freed memory in the heap for the
 * process's short life reuses it instead, for a few hundred KiB more peak
 * RSS. The daemon keeps glibc's defaults: between cycles it gives memory back. */
static void keep_freed_memory(void)
{
    enum { LARGEST_REUSED_BLOCK = 16 << 20, HEAP_KEPT = 16 << 20 };
    mallopt(M_MMAP_THRESHOLD, LARGEST_REUSED_BLOCK);
    mallopt(M_TRIM_THRESHOLD, HEAP_KEPT);
}

static const struct option replay_options[] = {
    {"replay", required_argument, 0, OPT_REPLAY},
    {"baseline", required_argument, 0, OPT_BASELINE},
    {"out", required_argument, 0, OPT_OUT},
    {"migration", required_argument, 0, OPT_MIGRATION},
    {"target-z", required_argument, 0, OPT_TARGET_Z},
    {"winding-span", required_argument, 0, OPT_WINDING_SPAN},
    {"time-zero-offset-ps", required_argument, 0, OPT_T0},
    {"watch-mm", required_argument, 0, OPT_WATCH},
    {"alarm-mm", required_argument, 0, OPT_ALARM},
    {"max-uncertainty-mm", required_argument, 0, OPT_MAX_UNC},
    {"edge-fraction", required_argument, 0, OPT_EDGE_FRACTION},
    {"direct-coupling-window-ns", required_argument, 0, OPT_DC_WINDOW},
    {"direct-coupling-tolerance-ps", required_argument, 0, OPT_DC_TOLERANCE},
    {"text", no_argument, 0, OPT_TEXT},
    {"help", no_argument, 0, 'h'},
    {"version", no_argument, 0, OPT_VERSION},
    {0, 0, 0, 0},
};

/* What the command line asks for. */
struct replay_args {
    const char *replay, *baseline_path, *out_dir;
    struct uwb_evaluate_options opt;
    int watch_given, alarm_given;
    int as_text; /* --text: the verdict for people, not its JSON line */
};

/* Returned by the option readers when the replay goes on. */
#define REPLAY_GOES_ON (-1)

/* --watch-mm, --alarm-mm, --max-uncertainty-mm: a positive number of millimetres. */
static int read_threshold(int c, const char *text, struct replay_args *a)
{
    const char *name = c == OPT_WATCH ? "--watch-mm" : c == OPT_ALARM ? "--alarm-mm" : "--max-uncertainty-mm";
    double v = 0;
    if (parse_number(name, text, &v) != 0)
        return EX_USAGE;
    if (!(v > 0.0)) {
        fprintf(stderr, "uwbd: %s: '%s' is not a positive number of millimetres\n", name, text);
        return EX_USAGE;
    }
    if (c == OPT_WATCH) {
        a->opt.compare.thresholds.watch_m = v * 1e-3;
        a->watch_given = 1;
    } else if (c == OPT_ALARM) {
        a->opt.compare.thresholds.alarm_m = v * 1e-3;
        a->alarm_given = 1;
    } else {
        a->opt.compare.max_uncertainty_m = v * 1e-3;
    }
    return REPLAY_GOES_ON;
}

/* The analysis options' values (--migration, --target-z, --time-zero-offset-ps,
 * --edge-fraction). */
static int read_analysis_option(int c, const char *text, struct uwb_analysis_options *analysis)
{
    double v = 0, near_m, far_m;
    switch (c) {
    case OPT_MIGRATION:
        if (uwb_migration_kind_parse(text, &analysis->migration) == 0)
            return REPLAY_GOES_ON;
        fprintf(stderr, "uwbd: --migration: '%s' is neither fixed nor float\n", text);
        return EX_USAGE;
    case OPT_TARGET_Z:
        if (parse_target_z(text, &near_m, &far_m) != 0) {
            fprintf(stderr, "uwbd: --target-z: '%s' is not NEAR:FAR with 0 <= NEAR < FAR (metres)\n", text);
            return EX_USAGE;
        }
        analysis->has_target_z = 1;
        analysis->target_z_m[0] = near_m;
        analysis->target_z_m[1] = far_m;
        return REPLAY_GOES_ON;
    case OPT_WINDING_SPAN: {
        if (parse_pair(text, &near_m, &far_m) != 0) {
            fprintf(stderr, "uwbd: --winding-span: '%s' is not LOW:HIGH with LOW < HIGH (metres)\n", text);
            return EX_USAGE;
        }
        double span_m[2] = {near_m, far_m};
        char problem[200];
        if (uwbd_winding_span_check(span_m, problem, sizeof problem) != 0) {
            fprintf(stderr, "uwbd: --winding-span: '%s': %s (the limits of " UWBD_WINDING_SPAN_KEY ")\n",
                    text, problem);
            return EX_USAGE;
        }
        analysis->has_winding_span = 1;
        analysis->winding_span_m[0] = near_m;
        analysis->winding_span_m[1] = far_m;
        return REPLAY_GOES_ON;
    }
    case OPT_T0:
        if (parse_number("--time-zero-offset-ps", text, &v) != 0)
            return EX_USAGE;
        analysis->time_zero_offset_s = v * 1e-12;
        return REPLAY_GOES_ON;
    default: /* OPT_EDGE_FRACTION */
        if (parse_number("--edge-fraction", text, &v) != 0 || !(v > 0.05 && v < 0.95)) {
            fprintf(stderr, "uwbd: --edge-fraction: '%s' must lie between 0.05 and 0.95\n", text);
            return EX_USAGE;
        }
        analysis->edge_fraction = v;
        return REPLAY_GOES_ON;
    }
}

/* --direct-coupling-window-ns and --direct-coupling-tolerance-ps. */
static int read_direct_coupling_option(int c, const char *text, struct uwb_direct_coupling_options *dc)
{
    double v = 0;
    if (c == OPT_DC_WINDOW) {
        if (parse_number("--direct-coupling-window-ns", text, &v) != 0)
            return EX_USAGE;
        dc->window_end_s = v * 1e-9;
        return REPLAY_GOES_ON;
    }
    if (parse_number("--direct-coupling-tolerance-ps", text, &v) != 0)
        return EX_USAGE;
    if (!(v > 0.0)) {
        fprintf(stderr,
                "uwbd: --direct-coupling-tolerance-ps: '%s' is not a positive number of picoseconds\n", text);
        return EX_USAGE;
    }
    dc->tolerance_s = v * 1e-12;
    return REPLAY_GOES_ON;
}

/* One option: REPLAY_GOES_ON, or the exit status (--help, --version, an error). */
static int read_option(int c, int argc, char **argv, struct replay_args *a)
{
    switch (c) {
    case OPT_REPLAY: a->replay = optarg; return REPLAY_GOES_ON;
    case OPT_BASELINE: a->baseline_path = optarg; return REPLAY_GOES_ON;
    case OPT_OUT: a->out_dir = optarg; return REPLAY_GOES_ON;
    case OPT_TEXT: a->as_text = 1; return REPLAY_GOES_ON;
    case OPT_MIGRATION:
    case OPT_TARGET_Z:
    case OPT_WINDING_SPAN:
    case OPT_T0:
    case OPT_EDGE_FRACTION: return read_analysis_option(c, optarg, &a->opt.analysis);
    case OPT_WATCH:
    case OPT_ALARM:
    case OPT_MAX_UNC: return read_threshold(c, optarg, a);
    case OPT_DC_WINDOW:
    case OPT_DC_TOLERANCE: return read_direct_coupling_option(c, optarg, &a->opt.direct_coupling);
    case 'h': usage(stdout); return 0;
    case OPT_VERSION: printf("uwbd %s\n", UWBD_VERSION); return 0;
    default: uwb_cli_option_error("uwbd", "uwbd --help", argv, argc, replay_options); return EX_USAGE;
    }
}

/* The command line into *a: REPLAY_GOES_ON, or the exit status. */
static int read_args(int argc, char **argv, struct replay_args *a)
{
    memset(a, 0, sizeof *a);
    uwb_evaluate_defaults(&a->opt);
    int c;
    opterr = 0; /* one line of our own instead of getopt's and the usage */
    while ((c = getopt_long(argc, argv, "h", replay_options, NULL)) != -1) {
        int rc = read_option(c, argc, argv, a);
        if (rc != REPLAY_GOES_ON)
            return rc;
    }
    if (optind < argc) {
        uwb_cli_unexpected_argument("uwbd", argv, optind, argc);
        return EX_USAGE;
    }
    if (!a->replay) {
        fprintf(stderr,
                "uwbd: nothing to do: give --replay FILE, --config FILE or ctl COMMAND (see --help)\n");
        return EX_USAGE;
    }
    const struct uwb_thresholds *t = &a->opt.compare.thresholds;
    if (t->alarm_m < t->watch_m) {
        /* Both values, and which one is a default, so the fix is plain. */
        fprintf(stderr,
                "uwbd: --alarm-mm %g%s is below --watch-mm %g%s: the alarm threshold must be at least the "
                "watch threshold\n",
                t->alarm_m * 1e3, a->alarm_given ? "" : " (the default)", t->watch_m * 1e3,
                a->watch_given ? "" : " (the default)");
        return EX_USAGE;
    }
    return REPLAY_GOES_ON;
}

/* The scans (and what was recorded with the baseline) read, the output
 * directory made. 0, or the exit status with nothing left allocated. */
static int read_inputs(const struct replay_args *a, struct uwb_scan *current, struct uwb_scan *baseline,
                       struct uwb_baseline_record *record)
{
    int rc = read_scan(a->replay, current);
    if (rc)
        return rc;
    if (a->baseline_path && ((rc = read_scan(a->baseline_path, baseline)) != 0 ||
                             (rc = baseline_record(a->baseline_path, baseline, record)) != 0))
        goto fail;
    if (a->out_dir && mkdir(a->out_dir, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "uwbd: %s: cannot create output directory: %s\n", a->out_dir, strerror(errno));
        rc = EX_CANTCREAT;
        goto fail;
    }
    return 0;
fail:
    uwb_scan_free(current);
    uwb_scan_free(baseline);
    return rc;
}

/* The images (--out) and the verdict line, on stdout and beside them. */
static int write_outputs(const struct replay_args *a, const struct uwb_scan *current,
                         const struct uwb_analysis *cur_a, const struct uwb_analysis *base_a,
                         struct uwb_verdict *verdict)
{
    int rc = 0;
    char stem[128], err[512];
    image_stem(current, a->replay, stem, sizeof stem);
    struct uwb_provenance site = {.thresholds = &a->opt.compare.thresholds,
                                  .radial_thresholds = &a->opt.compare.radial_thresholds};
    if (a->out_dir &&
        uwb_write_images(a->out_dir, stem, &site, current, cur_a, base_a, verdict, err, sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s\n", err);
        rc = EX_CANTCREAT;
    }
    char *json = uwb_verdict_to_json(verdict);
    if (!json) {
        fprintf(stderr, "uwbd: out of memory for the verdict\n");
        return EX_SOFTWARE;
    }
    if (a->out_dir && rc == 0 && write_verdict_file(a->out_dir, stem, json) != 0)
        rc = EX_CANTCREAT;
    /* "±" or "+/-" as the terminal's codeset allows (LC_CTYPE only). */
    setlocale(LC_CTYPE, "");
    if (!a->as_text || uwbd_verdict_text_in(json, stdout, uwbd_charset_of_locale()) != 0)
        puts(json);
    free(json);
    return rc;
}

int uwbd_replay_main(int argc, char **argv)
{
    struct replay_args a;
    int rc = read_args(argc, argv, &a);
    if (rc != REPLAY_GOES_ON)
        return rc;
    keep_freed_memory();
    struct uwb_scan current = {0}, baseline = {0};
    struct uwb_baseline_record record;
    rc = read_inputs(&a, &current, &baseline, &record);
    if (rc)
        return rc;
    struct uwb_verdict verdict;
    struct uwb_analysis cur_a, base_a;
    char err[512];
    if (uwb_evaluate(&current, a.baseline_path ? &record : NULL, &a.opt, &verdict, &cur_a, &base_a, err,
                     sizeof err) != 0) {
        fprintf(stderr, "uwbd: %s: %s\n", a.replay, err);
        rc = EX_SOFTWARE;
    } else {
        rc = write_outputs(&a, &current, &cur_a, &base_a, &verdict);
        uwb_analysis_free(&cur_a);
        uwb_analysis_free(&base_a);
    }
    uwb_scan_free(&current);
    uwb_scan_free(&baseline);
    return rc;
}
