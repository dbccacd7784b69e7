/* The same tank, nothing moved, the oil warmer or colder than at the
 * baseline: its eps_r off the header's, which stays (as a configured
 * permittivity reads). The oil's wave speed moves the face's range and the
 * image, focused at the header's speed, blurs the shoulders differently:
 * the crossings read a height change that is none. The tanks: the shared
 * full-wave tank's winding in the simulator (with a direct coupling for
 * the time zero) drawn over the family's ranges (5-8 disks, faces at
 * 390-490 mm, pulses of 1.8-2.6 GHz); the oils: eps_r 2.16 and 2.26
 * against the header's 2.2. */
#include "accuracy/warm_oil.h"

#include <math.h>
#include <string.h>

#include "uwb/evaluate.h"
#include "uwbsim/scene.h"
#include "uwbsim/simulate.h"

#define SCENE "tools/uwbsim/scenes/fdtd2d-tank-winding.json"

/* Each tank's settings (key, value, ... NULL) over the scene's. */
static const char *const tanks[][7] = {
    {NULL},
    {"face_z_m", "0.49", NULL},
    {"face_z_m", "0.39", "disks", "5", NULL},
    {"disks", "8", "disk_height_m", "0.024", NULL},
    {"centre_frequency_hz", "1.8e9", NULL},
    {"centre_frequency_hz", "2.6e9", "face_z_m", "0.46", NULL},
};
static const char *const oils[] = {"2.16", "2.26"};

static int set_all(struct sim_scene *scene, const char *const *kv, char *err, size_t errlen)
{
    for (int i = 0; kv[i]; i += 2)
        if (sim_scene_set(scene, kv[i], kv[i + 1], err, errlen) != 0)
            return -1;
    return 0;
}

static int one_pair(FILE *out, size_t tank, const char *oil, struct warm_oil_tally *t, char *err,
                    size_t errlen)
{
    static const char *const coupling[] = {"coupling_gain", "0.05", "t0_s", "-1e-9", NULL};
    const char *const changed[] = {"eps_r", oil, NULL};
    struct sim_scene scene;
    if (sim_scene_default(&scene) != 0 || sim_scene_load_json(SCENE, &scene, err, errlen) != 0 ||
        set_all(&scene, coupling, err, errlen) != 0 || set_all(&scene, tanks[tank], err, errlen) != 0)
        return -1;
    struct uwb_scan base, cur;
    if (sim_make_scan(&scene, 1, &base, err, errlen) != 0)
        return -1;
    if (set_all(&scene, changed, err, errlen) != 0 || sim_make_scan(&scene, 1, &cur, err, errlen) != 0) {
        uwb_scan_free(&base);
        return -1;
    }
    cur.eps_r = base.eps_r; /* the header's, configured; the oil's own changed */
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_analysis ca, ba;
    struct uwb_verdict v;
    struct uwb_baseline_record rec = {.scan = &base};
    int rc = uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, errlen);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    if (rc != 0)
        return -1;
    double moved = (ca.edges.face_z_m - ba.edges.face_z_m) * 1e3;
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    t->pairs++;
    t->shift_within += fabs(v.axial_displacement_m) <= 2.0 * v.uncertainty_m;
    fprintf(out, "| %zu | %s | %+.2f | %+.2f ± %.2f | ", tank, oil, moved, v.axial_displacement_m * 1e3,
            v.uncertainty_m * 1e3);
    if (v.height_change_withheld[0]) {
        fprintf(out, "withheld: %s |\n", v.height_change_withheld);
        return 0;
    }
    double ratio = v.height_change_m / v.height_change_uncertainty_m;
    t->given++;
    t->within += fabs(ratio) <= 2.0;
    fprintf(out, "%+.2f ± %.2f (%+.1f σ) |\n", v.height_change_m * 1e3, v.height_change_uncertainty_m * 1e3,
            ratio);
    return 0;
}

int accuracy_warm_oil(FILE *out, struct warm_oil_tally *t, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    fprintf(out,
            "| tank | oil eps_r (header 2.2) | face range moved, mm | shift ± σ | height change ± σ |\n");
    fprintf(out, "|---|---|---|---|---|\n");
    for (size_t k = 0; k < sizeof tanks / sizeof tanks[0]; k++)
        for (size_t o = 0; o < sizeof oils / sizeof oils[0]; o++)
            if (one_pair(out, k, oils[o], t, err, errlen) != 0)
                return -1;
    fprintf(out, "\nwarm oil: %d pairs, %d height changes given, %d within 2σ of none; %d shifts within 2σ\n",
            t->pairs, t->given, t->within, t->shift_within);
    return 0;
}
