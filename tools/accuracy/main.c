/* uwbaccuracy: the accuracy report (make accuracy). Prints a markdown table;
 * with --readme FILE it also puts the table between FILE's markers. */
#define _GNU_SOURCE /* open_memstream */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy/accuracy.h"
#include "accuracy/model_term.h"
#include "accuracy/radial.h"
#include "accuracy/tank3d.h"
#include "accuracy/targets.h"
#include "accuracy/warm_oil.h"
#include "uwb/atomic_file.h"
#include "uwb/evaluate.h"
#include "uwb/read_file.h"

#define BEGIN_MARK "<!-- make accuracy: begin -->\n"
#define END_MARK "<!-- make accuracy: end -->\n"
#define RADIAL_BEGIN_MARK "<!-- make accuracy radial: begin -->\n"
#define RADIAL_END_MARK "<!-- make accuracy radial: end -->\n"
#define TANK3D_BEGIN_MARK "<!-- make accuracy 3-D: begin -->\n"
#define TANK3D_END_MARK "<!-- make accuracy 3-D: end -->\n"
#define MODEL_BEGIN_MARK "<!-- make accuracy-model-term: begin -->\n"
#define MODEL_END_MARK "<!-- make accuracy-model-term: end -->\n"
#define TARGETS_BEGIN_MARK "<!-- make accuracy targets: begin -->\n"
#define TARGETS_END_MARK "<!-- make accuracy targets: end -->\n"

/* The radial rows' noisy level: the 32 dB (3 ps, 2 %). */
#define RADIAL_LEVEL 1

static int replace_block(const char *path, const char *table, const char *begin_mark, const char *end_mark,
                         char *err, size_t errlen)
{
    size_t len;
    char *text = NULL;
    if (uwb_read_file(path, 4u << 20, &text, &len, err, errlen) != 0)
        return -1;
    char *begin = strstr(text, begin_mark), *end = begin ? strstr(begin, end_mark) : NULL;
    if (!begin || !end) {
        snprintf(err, errlen, "%s: no block between \"%.40s\" and \"%.40s\"", path, begin_mark, end_mark);
        free(text);
        return -1;
    }
    begin += strlen(begin_mark);
    size_t head = (size_t)(begin - text), tail = len - (size_t)(end - text), body = strlen(table);
    char *out = malloc(head + body + tail + 1); /* NUL-terminated, though written by length */
    if (!out) {
        snprintf(err, errlen, "out of memory");
        free(text);
        return -1;
    }
    memcpy(out, text, head);
    memcpy(out + head, table, body);
    memcpy(out + head + body, end, tail);
    out[head + body + tail] = '\0';
    int rc = uwb_atomic_write_file(path, out, head + body + tail, err, errlen);
    free(out);
    free(text);
    return rc;
}

/* A number argument in [lo, hi], the whole text read (strtod). */
static int number_arg(const char *what, const char *text, double lo, double hi, double *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !(v >= lo && v <= hi)) {
        fprintf(stderr, "uwbaccuracy: %s: '%s' is not a number from %g to %g\n", what, text, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

/* Noisy pairs per case. The issue asks for at least 30, but over 30 pairs a
 * spread scatters by about 13 % of itself and a share by about 5 %, as wide
 * as the gaps the report is read for (spread / sigma up to 1.25, 90 %
 * within 2 sigma); over 150 it is about 6 % and 2.5 %, in some 3 minutes. */
#define REPORT_PAIRS 150

/* Issue 45's goal for a lean: one of the alarm limit or more (the 6 mm
 * leans) reads its tilt within this of the truth. */
#define LEAN_GOAL_M 0.0015

/* The radial rows: every case clean, the changes also over noisy pairs;
 * into mem as well when not NULL. 0, or 1 with the error printed;
 * *leans_missed counts the leans past the alarm limit read off by more
 * than LEAN_GOAL_M or withheld (each printed as a missed target). */
static int radial_report(const char *dir, int pairs, FILE *mem, int *leans_missed)
{
    char err[512];
    int leans = 0;
    *leans_missed = 0;
    /* The misses go after the table (a line inside it would split it),
     * as the targets' do (targets.c). */
    char *miss_text = NULL;
    size_t miss_len = 0;
    FILE *misses = open_memstream(&miss_text, &miss_len);
    if (!misses) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 1;
    }
    struct uwb_evaluate_options defaults;
    uwb_evaluate_defaults(&defaults);
    double alarm_m = defaults.compare.radial_thresholds.alarm_m;
    radial_print_header(stdout);
    if (mem)
        radial_print_header(mem);
    for (int c = 0; c < radial_case_count; c++) {
        int noisy = radial_cases[c].change_m != 0.0 && !radial_cases[c].clean_only;
        for (int l = 0; l <= noisy; l++) {
            const struct accuracy_level *level = l ? &accuracy_levels[RADIAL_LEVEL] : NULL;
            struct radial_row row;
            unsigned long long seed = 7000000ull + 10000ull * (unsigned long long)c;
            if (radial_run_case(dir, &radial_cases[c], level, pairs, seed, &row, err, sizeof err) != 0) {
                fprintf(stderr, "uwbaccuracy: %s\n", err);
                fclose(misses);
                free(miss_text);
                return 1;
            }
            radial_print_row(stdout, &radial_cases[c], level, &row);
            if (mem)
                radial_print_row(mem, &radial_cases[c], level, &row);
            fflush(stdout);
            if (!level && radial_cases[c].change_m == 0.0 && fabs(radial_cases[c].tilt_m) >= alarm_m) {
                leans++;
                if (row.tilt_withheld || row.tilt_worst_m > LEAN_GOAL_M) {
                    char how[64] = "withheld";
                    if (!row.tilt_withheld)
                        snprintf(how, sizeof how, "read %.2f mm off", row.tilt_worst_m * 1e3);
                    fprintf(misses, "TARGET MISSED: %s: the tilt %s (the goal: within %.1f mm)\n",
                            radial_cases[c].name, how, LEAN_GOAL_M * 1e3);
                    (*leans_missed)++;
                }
            }
        }
    }
    char line[200];
    snprintf(line, sizeof line,
             "\nleans of %.0f mm or more: %d, their tilt read within %.1f mm: %d (the goal: all)\n",
             alarm_m * 1e3, leans, LEAN_GOAL_M * 1e3, leans - *leans_missed);
    fputs(line, stdout);
    if (mem)
        fputs(line, mem);
    fclose(misses);
    fputs(miss_text, stdout);
    if (mem)
        fputs(miss_text, mem);
    free(miss_text);
    return 0;
}

/* The 3-D rows: every moved scan clean, without and with the drawings'
 * span; into mem as well when not NULL. 0, or 1 with the error printed. */
static int tank3d_report(const char *dir, FILE *mem)
{
    char err[512];
    int within[2][2] = {{0, 0}, {0, 0}}, cases[2] = {0, 0};
    tank3d_print_header(stdout);
    if (mem)
        tank3d_print_header(mem);
    for (int c = 0; c < tank3d_case_count; c++) {
        cases[tank3d_cases[c].fresh]++;
        for (int with_span = 0; with_span <= 1; with_span++) {
            struct tank3d_row row;
            if (tank3d_run_case(dir, &tank3d_cases[c], with_span, &row, err, sizeof err) != 0) {
                fprintf(stderr, "uwbaccuracy: %s\n", err);
                return 1;
            }
            within[tank3d_cases[c].fresh][with_span] += row.within_2sigma;
            tank3d_print_row(stdout, &tank3d_cases[c], &row);
            if (mem)
                tank3d_print_row(mem, &tank3d_cases[c], &row);
            fflush(stdout);
        }
    }
    for (int fresh = 0; fresh <= 1; fresh++) {
        tank3d_print_count(stdout, fresh, within[fresh][0], within[fresh][1], cases[fresh]);
        if (mem)
            tank3d_print_count(mem, fresh, within[fresh][0], within[fresh][1], cases[fresh]);
    }
    return 0;
}

/* The model term's calibration (model_term.c) to stdout and, with a
 * README, between its markers there. */
static int model_term_report(const char *data_dir, const char *fresh_dir, const char *readme)
{
    char err[512], *table = NULL;
    size_t table_len = 0;
    FILE *mem = open_memstream(&table, &table_len);
    if (!mem) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 70;
    }
    double share;
    int rc = accuracy_model_term(mem, data_dir, fresh_dir, &share, err, sizeof err);
    fclose(mem);
    if (rc != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        free(table);
        return 1;
    }
    fputs(table, stdout);
    if (readme && replace_block(readme, table, MODEL_BEGIN_MARK, MODEL_END_MARK, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        rc = 73;
    }
    free(table);
    return rc;
}

/* The targets (targets.c) to stdout and, with a README, between its
 * markers there: 0 when every target holds, 1 when one is missed. */
static int targets_report(const char *data_dir, const char *fresh_dir, const char *readme)
{
    char err[512], *table = NULL;
    size_t table_len = 0;
    FILE *mem = open_memstream(&table, &table_len);
    if (!mem) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 70;
    }
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct accuracy_targets t;
    int rc = accuracy_targets_run(mem, data_dir, fresh_dir, &opt, &t, err, sizeof err);
    /* The height change's sigma over an oil change (the simulator's pairs). */
    struct warm_oil_tally oil;
    if (rc == 0) {
        fprintf(mem, "\nThe same tank, nothing moved, the oil's eps_r off the header's (simulator):\n\n");
        rc = accuracy_warm_oil(mem, &oil, err, sizeof err);
    }
    if (rc == 0 && (oil.within < oil.given || oil.shift_within < oil.pairs)) {
        fprintf(mem,
                "TARGET MISSED: warm oil: %d of %d height changes and %d of %d shifts within 2σ of none\n",
                oil.within, oil.given, oil.shift_within, oil.pairs);
        t.missed++;
    }
    fclose(mem);
    if (rc != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        free(table);
        return 1;
    }
    fputs(table, stdout);
    if (readme && replace_block(readme, table, TARGETS_BEGIN_MARK, TARGETS_END_MARK, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        free(table);
        return 73;
    }
    free(table);
    if (t.missed > 0) {
        fprintf(stderr, "uwbaccuracy: %d accuracy target(s) missed (lines TARGET MISSED above)\n", t.missed);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *dir = "tests/fixtures", *readme = NULL;
    int pairs = REPORT_PAIRS, only_case = -1, custom = 0, radial_only = 0, tank3d_only = 0;
    const char *model_data = NULL, *model_fresh = NULL, *targets_data = NULL, *targets_fresh = NULL;
    struct accuracy_level level_custom = {0};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--fixtures") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--pairs") && i + 1 < argc) {
            char *end;
            long n = strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end || n < 2 || n > 100000) {
                fprintf(stderr, "uwbaccuracy: --pairs: '%s' is not a whole number from 2 to 100000\n",
                        argv[i]);
                return 64;
            }
            pairs = (int)n;
        } else if (!strcmp(argv[i], "--readme") && i + 1 < argc)
            readme = argv[++i];
        else if (!strcmp(argv[i], "--case") && i + 1 < argc) {
            double n;
            if (number_arg("--case", argv[++i], 0, accuracy_case_count - 1, &n) != 0)
                return 64;
            if (n != (int)n) {
                fprintf(stderr, "uwbaccuracy: --case: '%s' is not a whole number\n", argv[i]);
                return 64;
            }
            only_case = (int)n;
        } else if (!strcmp(argv[i], "--model-term") && i + 2 < argc) {
            /* DATA_DIR FRESH_DIR: the axial sigma's share of the move, calibrated */
            model_data = argv[++i];
            model_fresh = argv[++i];
        } else if (!strcmp(argv[i], "--targets") && i + 2 < argc) {
            /* DATA_DIR FRESH_DIR: the targets, each figure against its truth */
            targets_data = argv[++i];
            targets_fresh = argv[++i];
        } else if (!strcmp(argv[i], "--radial"))
            radial_only = 1;
        else if (!strcmp(argv[i], "--3d"))
            tank3d_only = 1;
        else if (!strcmp(argv[i], "--pair-errors"))
            accuracy_log_pairs(stderr);
        else if (!strcmp(argv[i], "--impair") && i + 4 < argc) {
            /* SNR_DB (0: no white noise) JITTER_PS DRIFT_LINEAR DRIFT_RANDOM: one level instead of the
             * report's */
            custom = 1;
            double jitter_ps;
            if (number_arg("--impair SNR_DB", argv[++i], -100, 200, &level_custom.snr_db) != 0 ||
                number_arg("--impair JITTER_PS", argv[++i], 0, 1e6, &jitter_ps) != 0 ||
                number_arg("--impair DRIFT_LINEAR", argv[++i], 0, 1, &level_custom.drift_linear) != 0 ||
                number_arg("--impair DRIFT_RANDOM", argv[++i], 0, 1, &level_custom.drift_random) != 0)
                return 64;
            level_custom.jitter_s = jitter_ps * 1e-12;
        } else {
            fprintf(stderr, "usage: uwbaccuracy [--fixtures DIR] [--pairs N] [--readme FILE] [--case N] "
                            "[--pair-errors] [--radial] [--3d]\n"
                            "       [--model-term DATA_DIR FRESH_DIR] [--targets DATA_DIR FRESH_DIR]\n"
                            "       [--impair SNR_DB JITTER_PS DRIFT_LINEAR DRIFT_RANDOM]\n");
            return 64;
        }
    }
    if (model_data)
        return model_term_report(model_data, model_fresh, readme);
    if (targets_data)
        return targets_report(targets_data, targets_fresh, readme);
    if (radial_only) {
        int leans_missed;
        int rc = radial_report(dir, pairs, NULL, &leans_missed);
        return rc != 0 ? rc : leans_missed > 0;
    }
    if (tank3d_only)
        return tank3d_report(dir, NULL);
    if (readme && (custom || only_case >= 0)) {
        fprintf(stderr, "uwbaccuracy: --readme takes the whole report, not --case or --impair\n");
        return 64;
    }
    char err[512], *table = NULL;
    size_t table_len = 0;
    FILE *mem = open_memstream(&table, &table_len);
    if (!mem) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 70;
    }
    accuracy_print_header(stdout);
    accuracy_print_header(mem);
    for (int c = 0; c < accuracy_case_count; c++) {
        if (only_case >= 0 && c != only_case)
            continue;
        for (int l = custom ? 0 : -1; l < (custom ? 1 : accuracy_level_count); l++) {
            if (!custom && l >= 0 && l < accuracy_cases[c].from_level)
                continue;
            struct accuracy_row row;
            const struct accuracy_level *level = custom ? &level_custom : l < 0 ? NULL : &accuracy_levels[l];
            unsigned long long seed =
                1000000ull * (unsigned long long)(l + 1) + 10000ull * (unsigned long long)c;
            if (accuracy_run_case(dir, &accuracy_cases[c], level, pairs, seed, &row, err, sizeof err) != 0) {
                fprintf(stderr, "uwbaccuracy: %s\n", err);
                fclose(mem);
                free(table);
                return 1;
            }
            accuracy_print_row(stdout, &accuracy_cases[c], level, &row);
            accuracy_print_row(mem, &accuracy_cases[c], level, &row);
            fflush(stdout);
        }
    }
    fclose(mem);
    int rc = 0;
    if (readme && replace_block(readme, table, BEGIN_MARK, END_MARK, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        rc = 73;
    }
    free(table);
    if (rc != 0 || custom || only_case >= 0)
        return rc;
    printf("\n");
    table = NULL;
    table_len = 0;
    mem = open_memstream(&table, &table_len);
    if (!mem) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 70;
    }
    int leans_missed = 0;
    rc = radial_report(dir, pairs, mem, &leans_missed);
    fclose(mem);
    if (rc == 0 && readme &&
        replace_block(readme, table, RADIAL_BEGIN_MARK, RADIAL_END_MARK, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        rc = 73;
    }
    free(table);
    if (rc != 0)
        return rc;
    printf("\n");
    table = NULL;
    table_len = 0;
    mem = open_memstream(&table, &table_len);
    if (!mem) {
        fprintf(stderr, "uwbaccuracy: out of memory\n");
        return 70;
    }
    rc = tank3d_report(dir, mem);
    fclose(mem);
    if (rc == 0 && readme &&
        replace_block(readme, table, TANK3D_BEGIN_MARK, TANK3D_END_MARK, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        rc = 73;
    }
    free(table);
    if (rc == 0 && leans_missed > 0) {
        fprintf(stderr, "uwbaccuracy: %d lean(s) missed the goal (lines TARGET MISSED above)\n",
                leans_missed);
        rc = 1;
    }
    return rc;
}
