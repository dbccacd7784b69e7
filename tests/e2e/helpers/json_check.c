/* json_check: assertions on the daemon's JSON replies and files for the e2e
 * scripts and make test-board, with cJSON instead of a Python interpreter or jq, which
 * a fresh Debian minbase does not have.
 *
 *   json_check FILE CHECK...              FILE holds one JSON value ("-": stdin)
 *   json_check --each-line FILE CHECK...  every line of FILE is one JSON value,
 *                                         and every CHECK holds for each line
 *
 * A CHECK is one argument, "PATH OP [ARG]": PATH is dotted (array items by
 * index: images.0; "." is the whole value), ARG is the rest of the argument.
 *   PATH == TEXT       a string equal to TEXT
 *   PATH = JSON        equal to the JSON value JSON (true, 2, ["a","b"], ...)
 *   PATH same FILE     equal to the JSON value in FILE
 *   PATH ~ X TOL       a number within TOL of X
 *   PATH > N, >= N, < N, <= N    a number compared with N
 *   PATH is TYPE       number, string, bool, null, array or object
 *   PATH exists, PATH absent
 *   PATH len N         an array or object of N items
 *   PATH contains TEXT a string containing TEXT
 *   PATH matches ERE, PATH imatches ERE   a string matching the POSIX
 *                      extended regular expression (imatches: ignoring case)
 * Exit 0 when every check holds; 1 when one does not (each failure on stderr
 * with the value found); 2 when FILE cannot be read or is not JSON; 64 on a
 * malformed CHECK. */
#include <cjson/cJSON.h>
#include <math.h>
#include <regex.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "uwb/read_file.h"

#define MAX_FILE_BYTES ((size_t)64 * 1024 * 1024)
#define EXIT_FAILED 1
#define EXIT_UNREADABLE 2
#define EXIT_USAGE 64

static char *slurp(const char *path, size_t *len)
{
    char *text, err[1024];
    enum uwb_read_result r =
        strcmp(path, "-") == 0
            ? uwb_read_fd(STDIN_FILENO, "stdin", MAX_FILE_BYTES, &text, len, err, sizeof err)
            : uwb_read_file(path, MAX_FILE_BYTES, &text, len, err, sizeof err);
    if (r != UWB_READ_OK) {
        fprintf(stderr, "json_check: %s\n", err);
        return NULL;
    }
    return text;
}

/* One JSON value and nothing after it but white space, as json.load wants. */
static cJSON *parse_whole(const char *text, size_t len)
{
    const char *end = NULL;
    cJSON *v = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!v)
        return NULL;
    while (end < text + len && strchr(" \t\r\n", *end))
        end++;
    if (end != text + len) {
        cJSON_Delete(v);
        return NULL;
    }
    return v;
}

static cJSON *load(const char *path)
{
    size_t len;
    char *text = slurp(path, &len);
    if (!text)
        return NULL;
    cJSON *v = parse_whole(text, len);
    if (!v)
        fprintf(stderr, "json_check: %s: not one JSON value\n", path);
    free(text);
    return v;
}

static const cJSON *lookup(const cJSON *o, const char *path)
{
    if (strcmp(path, ".") == 0)
        return o;
    char key[256];
    while (o && *path) {
        size_t n = strcspn(path, ".");
        snprintf(key, sizeof key, "%.*s", (int)n, path);
        path += n + (path[n] == '.');
        if (cJSON_IsArray(o)) {
            char *end;
            long i = strtol(key, &end, 10);
            o = *end == '\0' && end != key ? cJSON_GetArrayItem(o, (int)i) : NULL;
        } else {
            o = cJSON_GetObjectItemCaseSensitive(o, key);
        }
    }
    return o;
}

static int parse_number(const char *s, double *out)
{
    char *end;
    *out = strtod(s, &end);
    return end != s && *end == '\0';
}

static int is_type(const cJSON *v, const char *type)
{
    if (strcmp(type, "number") == 0)
        return cJSON_IsNumber(v);
    if (strcmp(type, "string") == 0)
        return cJSON_IsString(v);
    if (strcmp(type, "bool") == 0)
        return cJSON_IsBool(v);
    if (strcmp(type, "null") == 0)
        return cJSON_IsNull(v);
    if (strcmp(type, "array") == 0)
        return cJSON_IsArray(v);
    if (strcmp(type, "object") == 0)
        return cJSON_IsObject(v);
    return -1;
}

static int regex_match(const char *text, const char *ere, int icase, int *usage)
{
    regex_t re;
    if (regcomp(&re, ere, REG_EXTENDED | REG_NOSUB | (icase ? REG_ICASE : 0)) != 0) {
        fprintf(stderr, "json_check: '%s' is not an extended regular expression\n", ere);
        *usage = 1;
        return 0;
    }
    int hit = regexec(&re, text, 0, NULL, 0) == 0;
    regfree(&re);
    return hit;
}

/* 1 the check holds, 0 it does not, -1 the check is malformed. */
static int holds(const cJSON *root, const char *path, const char *op, const char *arg)
{
    const cJSON *v = lookup(root, path);
    double x, tol;
    if (strcmp(op, "exists") == 0)
        return v != NULL;
    if (strcmp(op, "absent") == 0)
        return v == NULL;
    if (strcmp(op, "==") == 0)
        return cJSON_IsString(v) && strcmp(v->valuestring, arg) == 0;
    if (strcmp(op, "contains") == 0)
        return cJSON_IsString(v) && strstr(v->valuestring, arg) != NULL;
    if (strcmp(op, "matches") == 0 || strcmp(op, "imatches") == 0) {
        int usage = 0;
        int hit = cJSON_IsString(v) && regex_match(v->valuestring, arg, op[0] == 'i', &usage);
        if (!cJSON_IsString(v)) /* still report a malformed expression */
            regex_match("", arg, 0, &usage);
        return usage ? -1 : hit;
    }
    if (strcmp(op, "is") == 0) {
        int t = is_type(v, arg);
        return t < 0 ? -1 : v && t;
    }
    if (strcmp(op, "=") == 0 || strcmp(op, "same") == 0) {
        cJSON *want = op[0] == '=' ? parse_whole(arg, strlen(arg)) : load(arg);
        if (!want)
            return -1;
        int same = v && cJSON_Compare(v, want, 1);
        cJSON_Delete(want);
        return same;
    }
    if (strcmp(op, "len") == 0) {
        if (!parse_number(arg, &x))
            return -1;
        return (cJSON_IsArray(v) || cJSON_IsObject(v)) && cJSON_GetArraySize(v) == x;
    }
    if (strcmp(op, "~") == 0) {
        char xs[64], tols[64], extra;
        if (sscanf(arg, "%63s %63s %c", xs, tols, &extra) != 2 || !parse_number(xs, &x) ||
            !parse_number(tols, &tol))
            return -1;
        return cJSON_IsNumber(v) && fabs(v->valuedouble - x) <= tol;
    }
    if (!parse_number(arg, &x))
        return -1;
    if (strcmp(op, ">") == 0)
        return cJSON_IsNumber(v) && v->valuedouble > x;
    if (strcmp(op, ">=") == 0)
        return cJSON_IsNumber(v) && v->valuedouble >= x;
    if (strcmp(op, "<") == 0)
        return cJSON_IsNumber(v) && v->valuedouble < x;
    if (strcmp(op, "<=") == 0)
        return cJSON_IsNumber(v) && v->valuedouble <= x;
    return -1;
}

/* Runs every check on one value; an exit status. */
static int check_value(const cJSON *root, const char *where, int n_checks, char **checks)
{
    int status = 0;
    for (int i = 0; i < n_checks; i++) {
        char path[256], op[16];
        int used = 0;
        if (sscanf(checks[i], "%255s %15s%n", path, op, &used) != 2) {
            fprintf(stderr, "json_check: '%s' is not PATH OP [ARG]\n", checks[i]);
            return EXIT_USAGE;
        }
        const char *arg = checks[i] + used + (checks[i][used] == ' ');
        int ok = holds(root, path, op, arg);
        if (ok < 0) {
            fprintf(stderr, "json_check: '%s': unknown operator or bad argument\n", checks[i]);
            return EXIT_USAGE;
        }
        if (!ok) {
            const cJSON *v = lookup(root, path);
            char *found = v ? cJSON_PrintUnformatted(v) : NULL;
            fprintf(stderr, "json_check: %s: '%s' does not hold: %s is %s\n", where, checks[i], path,
                    v ? (found ? found : "?") : "absent");
            free(found);
            status = EXIT_FAILED;
        }
    }
    return status;
}

static int check_each_line(const char *path, int n_checks, char **checks)
{
    size_t len;
    char *text = slurp(path, &len);
    if (!text)
        return EXIT_UNREADABLE;
    int status = 0, line_no = 0;
    for (char *line = text; line < text + len && status != EXIT_USAGE;) {
        char *nl = memchr(line, '\n', (size_t)(text + len - line));
        size_t n = nl ? (size_t)(nl - line) : (size_t)(text + len - line);
        char where[4200];
        snprintf(where, sizeof where, "%s line %d", path, ++line_no);
        cJSON *v = parse_whole(line, n);
        if (!v) {
            fprintf(stderr, "json_check: %s: not one JSON value\n", where);
            status = status ? status : EXIT_UNREADABLE;
        } else {
            int s = check_value(v, where, n_checks, checks);
            status = s > status ? s : status;
        }
        cJSON_Delete(v);
        line += n + 1;
    }
    if (line_no == 0) {
        fprintf(stderr, "json_check: %s: no lines\n", path);
        status = EXIT_UNREADABLE;
    }
    free(text);
    return status;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "--each-line") == 0)
        return check_each_line(argv[2], argc - 3, argv + 3);
    if (argc < 2 || (argv[1][0] == '-' && argv[1][1] != '\0')) {
        fprintf(stderr, "usage: json_check [--each-line] FILE 'PATH OP [ARG]'...\n");
        return EXIT_USAGE;
    }
    cJSON *v = load(argv[1]);
    if (!v)
        return EXIT_UNREADABLE;
    int status = check_value(v, argv[1], argc - 2, argv + 2);
    cJSON_Delete(v);
    return status;
}
