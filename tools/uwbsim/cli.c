#include "bound.h"
#include "cli.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"
#include "simulate.h"
#include "uwb/atomic_file.h"
#include "uwb/scan.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: uwbsim [options] --seed N -o FILE.uwbscan [--truth FILE.json]\n"
                 "\n"
                 "Simulates a UWB radar scan of a transformer winding (physical optics) and\n"
                 "writes it as uwbscan/1. Options are applied in order, later ones win.\n"
                 "\n"
                 "  -o, --output FILE      the scan to write (atomically)\n"
                 "  --truth FILE           also write the true edges as JSON\n"
                 "  --seed N               seed of every random draw (default 1): same seed, same file\n"
                 "  --scene FILE           load a JSON scene: one object, keys = the parameters below\n"
                 "  --print-scene          print the effective scene as JSON and exit\n"
                 "  --precision-bound      print the Cramer-Rao bound on the displacement for the\n"
                 "                         scene's noise (snr_db, stack; white noise) as JSON and exit\n"
                 "  --params-markdown      print the parameter table as Markdown and exit\n"
                 "  -h, --help             this text\n"
                 "\n"
                 "Scene parameters: --name VALUE or --name=VALUE; in JSON files the same names\n"
                 "with '_' for '-'. Units in brackets; lengths in m, times in s.\n");
    sim_scene_print_help(out);
}

static int parse_seed(const char *text, uint64_t *seed)
{
    char *end;
    errno = 0;
    if (text[0] == '-')
        return -1;
    unsigned long long v = strtoull(text, &end, 0);
    if (end == text || *end != '\0' || errno == ERANGE)
        return -1;
    *seed = (uint64_t)v;
    return 0;
}

int uwbsim_cli(int argc, char **argv, FILE *out, FILE *errout)
{
    struct sim_scene scene;
    char err[512];
    if (sim_scene_default(&scene) != 0) {
        fprintf(errout, "uwbsim: parameter table has an invalid default\n");
        return 1;
    }
    const char *output = NULL, *truth = NULL;
    uint64_t seed = 1;
    int print_scene = 0, print_bound = 0;

    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            usage(out);
            return 0;
        }
        if (!strcmp(arg, "--params-markdown")) {
            sim_scene_print_markdown(out);
            return 0;
        }
        if (!strcmp(arg, "--print-scene")) {
            print_scene = 1;
            continue;
        }
        if (!strcmp(arg, "--precision-bound")) {
            print_bound = 1;
            continue;
        }
        if (strncmp(arg, "--", 2) != 0 && strcmp(arg, "-o") != 0) {
            fprintf(errout, "uwbsim: unexpected argument \"%s\" (see --help)\n", arg);
            return 2;
        }
        /* --name=value or --name value */
        char name[128];
        const char *value = NULL;
        const char *eq = strchr(arg, '=');
        const char *key = arg[1] == '-' ? arg + 2 : arg + 1;
        size_t klen = eq ? (size_t)(eq - key) : strlen(key);
        if (klen == 0 || klen >= sizeof name) {
            fprintf(errout, "uwbsim: bad option \"%s\"\n", arg);
            return 2;
        }
        memcpy(name, key, klen);
        name[klen] = '\0';
        if (eq) {
            value = eq + 1;
        } else {
            if (i + 1 >= argc) {
                fprintf(errout, "uwbsim: option %s needs a value\n", arg);
                return 2;
            }
            value = argv[++i];
        }
        if (!strcmp(name, "o") || !strcmp(name, "output")) {
            output = value;
        } else if (!strcmp(name, "truth")) {
            truth = value;
        } else if (!strcmp(name, "seed")) {
            if (parse_seed(value, &seed) != 0) {
                fprintf(errout, "uwbsim: --seed: expected a non-negative integer, got \"%s\"\n", value);
                return 2;
            }
        } else if (!strcmp(name, "scene")) {
            if (sim_scene_load_json(value, &scene, err, sizeof err) != 0) {
                fprintf(errout, "uwbsim: %s\n", err);
                return 2;
            }
        } else if (sim_scene_set(&scene, name, value, err, sizeof err) != 0) {
            fprintf(errout, "uwbsim: --%s\n", err);
            return 2;
        }
    }

    if (sim_scene_validate(&scene, err, sizeof err) != 0) {
        fprintf(errout, "uwbsim: %s\n", err);
        return 2;
    }
    if (print_scene) {
        char *json;
        if (sim_scene_to_json(&scene, &json) != 0) {
            fprintf(errout, "uwbsim: out of memory\n");
            return 1;
        }
        fprintf(out, "%s\n", json);
        free(json);
        return 0;
    }
    if (print_bound) {
        struct sim_bound b;
        if (sim_displacement_bound(&scene, &b, err, sizeof err) != 0) {
            fprintf(errout, "uwbsim: %s\n", err);
            return 1;
        }
        fprintf(out, "{\"noise_rms_v\": %.4g, \"single_scan_mm\": %.3f, \"displacement_mm\": %.3f}\n",
                b.noise_rms, b.single_scan_m * 1e3, b.displacement_m * 1e3);
        return 0;
    }
    if (!output) {
        fprintf(errout, "uwbsim: no output file (-o FILE.uwbscan); see --help\n");
        return 2;
    }

    struct uwb_scan scan;
    if (sim_make_scan(&scene, seed, &scan, err, sizeof err) != 0) {
        fprintf(errout, "uwbsim: %s\n", err);
        return 1;
    }
    int rc = uwbscan_write_file(output, &scan, err, sizeof err);
    uwb_scan_free(&scan);
    if (rc != 0) {
        fprintf(errout, "uwbsim: %s\n", err);
        return 1;
    }
    if (truth) {
        char *json;
        if (sim_truth_json(&scene, &json) != 0) {
            fprintf(errout, "uwbsim: out of memory\n");
            return 1;
        }
        size_t len = strlen(json);
        char *text = malloc(len + 2);
        if (!text) {
            free(json);
            fprintf(errout, "uwbsim: out of memory\n");
            return 1;
        }
        memcpy(text, json, len);
        text[len] = '\n';
        text[len + 1] = '\0';
        free(json);
        rc = uwb_atomic_write_file(truth, text, len + 1, err, sizeof err);
        free(text);
        if (rc != 0) {
            fprintf(errout, "uwbsim: %s\n", err);
            return 1;
        }
    }
    return 0;
}
