/* uwbaccuracy: the accuracy report (make accuracy). Prints a markdown table;
 * with --readme FILE it also puts the table between FILE's markers. */
#define _GNU_SOURCE /* open_memstream */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy/accuracy.h"
#include "uwb/atomic_file.h"
#include "uwb/read_file.h"

#define BEGIN_MARK "<!-- make accuracy: begin -->\n"
#define END_MARK "<!-- make accuracy: end -->\n"

static int replace_block(const char *path, const char *table, char *err, size_t errlen)
{
    size_t len;
    char *text = NULL;
    if (uwb_read_file(path, 4u << 20, &text, &len, err, errlen) != 0)
        return -1;
    char *begin = strstr(text, BEGIN_MARK), *end = begin ? strstr(begin, END_MARK) : NULL;
    if (!begin || !end) {
        snprintf(err, errlen, "%s: no block between \"%.30s\" and \"%.28s\"", path, BEGIN_MARK, END_MARK);
        free(text);
        return -1;
    }
    begin += strlen(BEGIN_MARK);
    size_t head = (size_t)(begin - text), tail = len - (size_t)(end - text), body = strlen(table);
    char *out = malloc(head + body + tail);
    if (!out) {
        snprintf(err, errlen, "out of memory");
        free(text);
        return -1;
    }
    memcpy(out, text, head);
    memcpy(out + head, table, body);
    memcpy(out + head + body, end, tail);
    int rc = uwb_atomic_write_file(path, out, head + body + tail, err, errlen);
    free(out);
    free(text);
    return rc;
}

int main(int argc, char **argv)
{
    const char *dir = "tests/fixtures", *readme = NULL;
    int pairs = 30, only_case = -1, custom = 0;
    struct accuracy_level level_custom = {0};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--fixtures") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--pairs") && i + 1 < argc)
            pairs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--readme") && i + 1 < argc)
            readme = argv[++i];
        else if (!strcmp(argv[i], "--case") && i + 1 < argc)
            only_case = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--pair-errors"))
            accuracy_log_pairs(stderr);
        else if (!strcmp(argv[i], "--impair") && i + 4 < argc) {
            /* SNR_DB (0: no white noise) JITTER_PS DRIFT_LINEAR DRIFT_RANDOM: one level instead of the
             * report's */
            custom = 1;
            level_custom.snr_db = atof(argv[++i]);
            level_custom.jitter_s = atof(argv[++i]) * 1e-12;
            level_custom.drift_linear = atof(argv[++i]);
            level_custom.drift_random = atof(argv[++i]);
        } else {
            fprintf(
                stderr,
                "usage: uwbaccuracy [--fixtures DIR] [--pairs N] [--readme FILE] [--case N] [--pair-errors]\n"
                "       [--impair SNR_DB JITTER_PS DRIFT_LINEAR DRIFT_RANDOM]\n");
            return 64;
        }
    }
    if (readme && (custom || only_case >= 0)) {
        fprintf(stderr, "uwbaccuracy: --readme takes the whole report, not --case or --impair\n");
        return 64;
    }
    if (pairs < 2) {
        fprintf(stderr, "uwbaccuracy: --pairs must be at least 2\n");
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
    if (readme && replace_block(readme, table, err, sizeof err) != 0) {
        fprintf(stderr, "uwbaccuracy: %s\n", err);
        rc = 73;
    }
    free(table);
    return rc;
}
