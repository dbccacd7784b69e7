/* The parameter table and the setters it drives. */
#include "scene.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const mode_choices[] = {"3d", "2d", NULL};
static const char *const polarisation_choices[] = {"parallel", "perpendicular", NULL};
static const char *const pulse_choices[] = {"ricker", "monocycle", "file", NULL};

#define OFF(field) offsetof(struct sim_scene, field)
#define NUM(name, unit, def, group, lo, hi, help) \
    { \
#name, SIM_PARAM_NUMBER, unit, def, group, help, OFF(name), lo, hi, NULL, NULL \
    }
#define OPTNUM(name, unit, group, lo, hi, help) \
    { \
#name, SIM_PARAM_OPTNUMBER, unit, "none", group, help, OFF(name), lo, hi, NULL, NULL \
    }
#define INT(name, def, group, lo, hi, help) \
    { \
#name, SIM_PARAM_INT, "", def, group, help, OFF(name), lo, hi, NULL, NULL \
    }
#define BOOL(name, def, group, help) \
    { \
#name, SIM_PARAM_BOOL, "", def, group, help, OFF(name), 0, 1, NULL, NULL \
    }
#define ENUM(name, def, group, choices, help) \
    { \
#name, SIM_PARAM_ENUM, "", def, group, help, OFF(name), 0, 0, choices, NULL \
    }
#define STR(name, group, help) \
    { \
#name, SIM_PARAM_STRING, "", "", group, help, OFF(name), 0, 0, NULL, NULL \
    }

static const struct sim_param params[] = {
    ENUM(mode, "3d", "general", mode_choices,
         "3d: disks are cylinders, point antennas; 2d: line source, every object infinitely long "
         "along x (to compare with 2-D FDTD)"),
    STR(description, "general", "free text describing the scene; written to the truth file only"),
    NUM(element_size_m, "m", "0", "general", 0, 0.1,
        "surface element size for the physical-optics integral; 0 = automatic (shortest "
        "wavelength in the medium / 8 in 3-D, / 16 in 2-D, taken at 3x the centre frequency)"),
    BOOL(edge_diffraction, "true", "general",
         "add the physical theory of diffraction's fringe term (exact wedge minus physical optics) along "
         "the stack's top and bottom edges (outer edges and inner rims), so corners diffract as a "
         "full-wave solver says"),

    NUM(eps_r, "", "2.2", "medium", 1, 100, "relative permittivity of the oil (written to the header)"),
    NUM(window_thickness_m, "m", "0.02", "medium", 0, 0.5,
        "thickness of the insulating window in the tank wall (0: no window)"),
    NUM(window_eps_r, "", "4.0", "medium", 1, 100, "relative permittivity of the window"),
    NUM(window_gap_m, "m", "0.005", "medium", 0, 0.5,
        "air between the antennas' phase centres (z = 0) and the window's outer face"),
    BOOL(window_echo, "true", "medium", "include the reflections from the window's two faces"),

    INT(disks, "6", "winding", 1, 500, "number of disks in the stack"),
    NUM(disk_height_m, "m", "0.022", "winding", 1e-4, 1, "axial height of one disk"),
    NUM(gap_m, "m", "0.004", "winding", 0, 1, "axial gap between neighbouring disks"),
    NUM(gap_eps_r, "", "0", "winding", 0, 100,
        "relative permittivity of what fills the gaps (perpendicular polarisation only: with parallel "
        "polarisation the gaps are closed); 0 = the oil itself (spacers elsewhere)"),
    NUM(outer_radius_m, "m", "0.15", "winding", 0.005, 5, "outer radius of the disks"),
    NUM(radial_build_m, "m", "0.06", "winding", 0.001, 5,
        "radial build (outer minus inner radius); in 2d mode, the depth of the disk rectangles"),
    NUM(face_z_m, "m", "0.45", "winding", 0.01, 20,
        "range of the winding's front face from the antenna line"),
    NUM(bottom_y_m, "m", "0.23", "winding", -20, 20,
        "height of the lowest disk's bottom before displacement"),
    NUM(displacement_m, "m", "0", "winding", -5, 5, "axial displacement of the whole stack, positive up"),
    NUM(height_change_m, "m", "0", "winding", -5, 5,
        "change of the stack height (elongation > 0, compression < 0), shared equally by the gaps; "
        "the stack's centre stays put"),
    NUM(tilt_deg, "deg", "0", "winding", -15, 15, "tilt of the stack's axis about its centre"),
    NUM(tilt_azimuth_deg, "deg", "0", "winding", -360, 360,
        "direction the top leans to: 0 = toward the antennas, 90 = sideways (+x); 3d mode only"),
    {"radial_m", SIM_PARAM_STRING, "m", "", "winding",
     "radial changes of the disks' front faces: FROM-TO:METRES or DISK:METRES, comma-separated, disks "
     "numbered 1..disks from the bottom; + toward the antennas (a bulge, free buckling outward), - away "
     "(a dent); a later entry wins where two overlap. The back face stays, the spacer between two moved "
     "disks moves with them; empty = none (e.g. 2-4:0.006)",
     OFF(radial_m), 0, 0, NULL, sim_radial_check},
    NUM(face_tilt_m, "m", "0", "winding", -1, 1,
        "the top disk's front this much nearer the antennas than the bottom disk's, linear over the disks "
        "between and added to radial_m (a lean of the face, not the axis tilt tilt_deg)"),

    BOOL(clutter, "true", "clutter",
         "master switch for the static clutter below (core, barrier, clamp, reference target, far wall)"),
    BOOL(core, "true", "clutter", "core leg behind the winding, a flat-fronted steel bar"),
    NUM(core_front_m, "m", "0.08", "clutter", 0, 5,
        "core leg's front face: distance in front of the winding axis"),
    NUM(core_width_m, "m", "0.15", "clutter", 0.001, 5, "width (along x) of the core leg's front face"),
    NUM(core_y_min_m, "m", "-0.4", "clutter", -20, 20,
        "lower end of the core leg (the default runs past the aperture)"),
    NUM(core_y_max_m, "m", "1.0", "clutter", -20, 20, "upper end of the core leg"),
    BOOL(barrier, "true", "clutter", "pressboard barrier: a thin dielectric cylinder around the winding"),
    NUM(barrier_gap_m, "m", "0.015", "clutter", 0.001, 5,
        "oil between the winding's outer face and the barrier"),
    NUM(barrier_thickness_m, "m", "0.003", "clutter", 1e-4, 0.1, "barrier thickness"),
    NUM(barrier_eps_r, "", "4.4", "clutter", 1, 100,
        "relative permittivity of the oil-impregnated pressboard"),
    NUM(barrier_y_min_m, "m", "-0.2", "clutter", -20, 20, "lower end of the barrier"),
    NUM(barrier_y_max_m, "m", "0.8", "clutter", -20, 20, "upper end of the barrier"),
    BOOL(clamp, "true", "clutter", "clamping plate above the winding: a horizontal steel plate"),
    NUM(clamp_y_m, "m", "0.47", "clutter", -20, 20, "height of the clamping plate's lower surface"),
    NUM(clamp_thickness_m, "m", "0.02", "clutter", 0.001, 1, "clamping plate thickness"),
    NUM(clamp_width_m, "m", "0.3", "clutter", 0.001, 5, "clamping plate width along x"),
    NUM(clamp_depth_m, "m", "0.25", "clutter", 0.001, 5, "clamping plate depth along z"),
    NUM(clamp_setback_m, "m", "0", "clutter", -1, 5,
        "range of the plate's front edge behind the winding's (undisplaced) face"),
    BOOL(reference, "false", "clutter",
         "the rig's fixed reference target: a small flat metal strip facing the antennas, fixed to the "
         "window frame in front of the winding, so the static scene varies with height and the rig "
         "check sees a slipped home switch; put it above or below the winding (level with the face it "
         "is taken for the face)"),
    NUM(reference_y_m, "m", "0.55", "clutter", -20, 20, "height of the reference target's centre"),
    NUM(reference_z_m, "m", "0.2", "clutter", 0.01, 20,
        "range of the reference target's face from the antenna line (between the window and the "
        "barrier)"),
    NUM(reference_height_m, "m", "0.025", "clutter", 0.001, 1, "reference target's height (along y)"),
    NUM(reference_width_m, "m", "0.05", "clutter", 0.001, 5, "reference target's width (along x)"),
    BOOL(far_wall, "true", "clutter", "the tank's far wall, a flat steel plane"),
    NUM(far_wall_z_m, "m", "1.4", "clutter", 0.01, 50, "range of the far wall"),
    NUM(far_wall_reflectivity, "", "0.3", "clutter", 0, 1,
        "magnitude of the far wall's reflection, lumping in the shadow cast by the core and windings"),

    NUM(tx_dy_m, "m", "-0.02", "antennas", -1, 1, "transmit phase centre, y offset from the reference point"),
    NUM(tx_dz_m, "m", "0", "antennas", -1, 1, "transmit phase centre, z offset"),
    NUM(rx_dy_m, "m", "0.02", "antennas", -1, 1, "receive phase centre, y offset"),
    NUM(rx_dz_m, "m", "0", "antennas", -1, 1, "receive phase centre, z offset"),
    NUM(beamwidth_deg, "deg", "70", "antennas", 0, 180,
        "full -3 dB beamwidth of each antenna (pattern cos^n of the angle off boresight +z); 0 = isotropic"),
    ENUM(polarisation, "parallel", "antennas", polarisation_choices,
         "E-field relative to the disk edges: parallel (horizontal E; gaps far below their cutoff look "
         "closed, edges are soft wedges; what 2-D TMz FDTD computes) or perpendicular (vertical E; gaps "
         "open, their faces lit through the mouth, edges are hard wedges)"),
    ENUM(pulse, "ricker", "antennas", pulse_choices,
         "pulse shape: ricker (t = 0 at its peak), monocycle (Gaussian first derivative, t = 0 at its "
         "zero crossing) or file (pulse_file)"),
    STR(pulse_file, "antennas",
        "measured pulse: text, one 'time_s value' pair per line, '#' comments, t = 0 when the pulse "
        "leaves the transmitter"),
    NUM(centre_frequency_hz, "Hz", "2e9", "antennas", 1e6, 1e12,
        "centre (peak spectral) frequency of the pulse"),
    NUM(pulse_derivative, "", "0", "antennas", 0, 3,
        "fractional time-derivative order applied to the shape to give the radiated field; 0.5 "
        "reproduces a 2-D FDTD line source driven by that shape"),
    NUM(pulse_amplitude, "V", "0.25", "antennas", -1e9, 1e9,
        "peak of the incident field 1 m from the transmitter (negative flips the polarity)"),
    NUM(coupling_gain, "", "0.05", "antennas", 0, 100,
        "direct Tx-Rx coupling relative to free-space propagation between the phase centres; 0 = none"),

    NUM(sample_interval_s, "s", "1e-11", "digitiser", 1e-14, 1e-6, "time between samples"),
    INT(samples, "2048", "digitiser", 16, 1048576, "samples per trace"),
    NUM(t0_s, "s", "-1e-9", "digitiser", -1e-3, 1e-3,
        "time of sample 0 after the pulse leaves the transmitter"),
    INT(adc_bits, "12", "digitiser", 0, 24, "ADC resolution; 0 = ideal (no quantisation, no clipping)"),
    NUM(adc_full_scale_v, "V", "0.5", "digitiser", 1e-9, 1e9,
        "ADC full scale: codes span -FS..+FS, beyond clips"),
    INT(stack, "1", "digitiser", 1, 65536, "pulses averaged per trace (each digitised on its own)"),
    BOOL(noise, "true", "digitiser", "add receiver noise"),
    NUM(snr_db, "dB", "30", "digitiser", -40, 200,
        "per-pulse SNR: 20 log10(peak |winding echo| / noise rms), the peak taken over all positions of "
        "the noiseless winding-only scan; stacking improves it by sqrt(stack)"),
    NUM(noise_bandwidth_hz, "Hz", "0", "digitiser", 0, 1e13,
        "receiver noise bandwidth: the noise is flat up to it and absent above (same rms per sample); "
        "0 = white up to Nyquist. A real front end's is a few GHz, which leaves more noise in the "
        "pulse's band at the same snr_db"),
    NUM(jitter_s, "s", "2e-12", "digitiser", 0, 1e-9, "rms trigger jitter, one random shift per trace"),
    NUM(drift_db, "dB", "0.02", "digitiser", 0, 10,
        "rms step of the slow gain drift, a random walk from one position to the next"),

    INT(positions, "21", "positions", 1, 4096, "number of antenna positions K"),
    NUM(position_step_m, "m", "0.03", "positions", -10, 10, "distance between positions"),
    NUM(first_position_m, "m", "0", "positions", -20, 20, "height of the first position"),

    OPTNUM(target_z_near_m, "m", "header", 0, 50,
           "header target_z_m[0]: where the installation expects the face, near"),
    OPTNUM(target_z_far_m, "m", "header", 0, 50, "header target_z_m[1], far (both or neither)"),
    STR(created, "header", "header 'created' (ISO-8601); empty = absent, so files stay reproducible"),
    STR(scan_id, "header", "header 'scan_id'; empty = absent"),
    STR(comment, "header", "header 'comment'; empty = absent. Never put the truth here"),
};

const struct sim_param *sim_params(size_t *count)
{
    *count = sizeof params / sizeof params[0];
    return params;
}

const struct sim_param *sim_param_find(const char *key)
{
    char canon[128];
    size_t n = strlen(key);
    if (n == 0 || n >= sizeof canon)
        return NULL;
    for (size_t i = 0; i <= n; i++)
        canon[i] = key[i] == '-' ? '_' : key[i];
    for (size_t i = 0; i < sizeof params / sizeof params[0]; i++)
        if (strcmp(params[i].name, canon) == 0)
            return &params[i];
    return NULL;
}

static int parse_double(const char *text, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || errno == ERANGE)
        return -1;
    while (isspace((unsigned char)*end))
        end++;
    if (*end != '\0' || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int set_param(struct sim_scene *scene, const struct sim_param *p, const char *value, char *err,
                     size_t errlen)
{
    char *base = (char *)scene + p->offset;
    switch (p->type) {
    case SIM_PARAM_NUMBER:
    case SIM_PARAM_OPTNUMBER: {
        double v;
        if (p->type == SIM_PARAM_OPTNUMBER && (strcmp(value, "none") == 0 || strcmp(value, "null") == 0)) {
            double none = NAN;
            memcpy(base, &none, sizeof none); /* the field is a double at p->offset */
            return 0;
        }
        if (parse_double(value, &v) != 0) {
            snprintf(err, errlen, "%s: expected a number%s, got \"%s\"", p->name,
                     p->type == SIM_PARAM_OPTNUMBER ? " or none" : "", value);
            return -1;
        }
        if (v < p->min || v > p->max) {
            snprintf(err, errlen, "%s: %g is outside [%g, %g]%s%s", p->name, v, p->min, p->max,
                     p->unit[0] ? " " : "", p->unit);
            return -1;
        }
        memcpy(base, &v, sizeof v);
        return 0;
    }
    case SIM_PARAM_INT: {
        double v;
        if (parse_double(value, &v) != 0 || v != floor(v)) {
            snprintf(err, errlen, "%s: expected an integer, got \"%s\"", p->name, value);
            return -1;
        }
        if (v < p->min || v > p->max) {
            snprintf(err, errlen, "%s: %g is outside [%g, %g]", p->name, v, p->min, p->max);
            return -1;
        }
        *(int *)base = (int)v;
        return 0;
    }
    case SIM_PARAM_BOOL:
        if (!strcmp(value, "true") || !strcmp(value, "on") || !strcmp(value, "yes") || !strcmp(value, "1")) {
            *(int *)base = 1;
            return 0;
        }
        if (!strcmp(value, "false") || !strcmp(value, "off") || !strcmp(value, "no") || !strcmp(value, "0")) {
            *(int *)base = 0;
            return 0;
        }
        snprintf(err, errlen, "%s: expected true or false, got \"%s\"", p->name, value);
        return -1;
    case SIM_PARAM_ENUM:
        for (int i = 0; p->choices[i]; i++) {
            if (strcmp(p->choices[i], value) == 0) {
                *(int *)base = i;
                return 0;
            }
        }
        {
            char list[256] = "";
            for (int i = 0; p->choices[i]; i++) {
                strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
                strncat(list, p->choices[i], sizeof list - strlen(list) - 1);
            }
            snprintf(err, errlen, "%s: expected one of %s, got \"%s\"", p->name, list, value);
        }
        return -1;
    case SIM_PARAM_STRING:
        if (strlen(value) >= SIM_TEXT_MAX) {
            snprintf(err, errlen, "%s: text longer than %d bytes", p->name, SIM_TEXT_MAX - 1);
            return -1;
        }
        if (p->check && p->check(value, err, errlen) != 0)
            return -1;
        memcpy(base, value, strlen(value) + 1); /* length checked above */
        return 0;
    }
    snprintf(err, errlen, "%s: parameter of unknown type", p->name);
    return -1;
}

int sim_scene_set(struct sim_scene *scene, const char *key, const char *value, char *err, size_t errlen)
{
    const struct sim_param *p = sim_param_find(key);
    if (!p) {
        snprintf(err, errlen, "%s: unknown parameter", key);
        return -1;
    }
    return set_param(scene, p, value, err, errlen);
}

int sim_scene_default(struct sim_scene *scene)
{
    char err[256];
    memset(scene, 0, sizeof *scene);
    for (size_t i = 0; i < sizeof params / sizeof params[0]; i++)
        if (set_param(scene, &params[i], params[i].def, err, sizeof err) != 0)
            return -1; /* a default that its own setter refuses: table bug */
    return 0;
}

void sim_scene_get(const struct sim_scene *scene, const struct sim_param *p, char *buf, size_t buflen)
{
    const char *base = (const char *)scene + p->offset;
    switch (p->type) {
    case SIM_PARAM_NUMBER:
    case SIM_PARAM_OPTNUMBER: {
        double v;
        memcpy(&v, base, sizeof v);
        if (isnan(v))
            snprintf(buf, buflen, "none");
        else
            snprintf(buf, buflen, "%.17g", v);
        return;
    }
    case SIM_PARAM_INT: snprintf(buf, buflen, "%d", *(const int *)base); return;
    case SIM_PARAM_BOOL: snprintf(buf, buflen, "%s", *(const int *)base ? "true" : "false"); return;
    case SIM_PARAM_ENUM: snprintf(buf, buflen, "%s", p->choices[*(const int *)base]); return;
    case SIM_PARAM_STRING: snprintf(buf, buflen, "%s", base); return;
    }
    if (buflen)
        buf[0] = '\0';
}

double sim_scene_gap_actual_m(const struct sim_scene *s)
{
    if (s->disks < 2)
        return s->gap_m;
    return s->gap_m + s->height_change_m / (s->disks - 1);
}

double sim_scene_pitch_m(const struct sim_scene *s)
{
    return s->disk_height_m + sim_scene_gap_actual_m(s);
}

double sim_scene_stack_height_m(const struct sim_scene *s)
{
    return s->disks * s->disk_height_m + (s->disks - 1) * sim_scene_gap_actual_m(s);
}

double sim_scene_nominal_center_y_m(const struct sim_scene *s)
{
    double nominal_height = s->disks * s->disk_height_m + (s->disks - 1) * s->gap_m;
    return s->bottom_y_m + 0.5 * nominal_height;
}

double sim_scene_antenna_y_m(const struct sim_scene *s, int position)
{
    /* rounded to the nanometre so 0.33 is written 0.33, not 0.32999999999999996 */
    return nearbyint((s->first_position_m + position * s->position_step_m) * 1e9) / 1e9;
}

/* Radial changes: every disk named exists, no front goes through its back
 * face, and none reaches the barrier or the tank window. */
static int validate_fronts(const struct sim_scene *s, char *err, size_t errlen)
{
    double front[SIM_DISKS_MAX];
    if (s->disks > SIM_DISKS_MAX) {
        snprintf(err, errlen, "disks: %d is more than %d", s->disks, SIM_DISKS_MAX);
        return -1;
    }
    if (sim_scene_disk_fronts(s, front, err, errlen) != 0)
        return -1;
    double clear = s->face_z_m - s->window_gap_m - s->window_thickness_m - 1e-3;
    const char *what = "the tank window";
    if (s->clutter && s->barrier) {
        clear = s->barrier_gap_m;
        what = "the barrier (barrier_gap_m)";
    }
    for (int i = 0; i < s->disks; i++) {
        if (front[i] <= -s->radial_build_m) {
            snprintf(err, errlen,
                     "radial_m, face_tilt_m: disk %d's front moves %g m away, through its back face "
                     "(radial_build_m = %g m)",
                     i + 1, -front[i], s->radial_build_m);
            return -1;
        }
        if (front[i] >= clear) {
            snprintf(err, errlen, "radial_m, face_tilt_m: disk %d's front moves %g m nearer and reaches %s",
                     i + 1, front[i], what);
            return -1;
        }
    }
    return 0;
}

int sim_scene_validate(const struct sim_scene *s, char *err, size_t errlen)
{
    if (s->disks > 1 && sim_scene_gap_actual_m(s) < 0) {
        snprintf(err, errlen, "height_change_m: %g m of compression closes the %d gaps of gap_m = %g m",
                 -s->height_change_m, s->disks - 1, s->gap_m);
        return -1;
    }
    if (s->radial_build_m > s->outer_radius_m && s->mode == SIM_MODE_3D) {
        snprintf(err, errlen, "radial_build_m: %g m is more than outer_radius_m = %g m", s->radial_build_m,
                 s->outer_radius_m);
        return -1;
    }
    if (s->window_gap_m + s->window_thickness_m >= s->face_z_m - 1e-3) {
        snprintf(err, errlen,
                 "window_gap_m + window_thickness_m: the window reaches the winding's face (face_z_m = %g m)",
                 s->face_z_m);
        return -1;
    }
    if (s->clutter && s->barrier &&
        s->window_gap_m + s->window_thickness_m >= s->face_z_m - s->barrier_gap_m - s->barrier_thickness_m) {
        snprintf(err, errlen, "barrier_gap_m: the barrier would overlap the tank window");
        return -1;
    }
    if (s->clutter && s->reference &&
        (s->reference_z_m <= s->window_gap_m + s->window_thickness_m ||
         s->reference_z_m >= s->face_z_m - (s->barrier ? s->barrier_gap_m + s->barrier_thickness_m : 0))) {
        snprintf(err, errlen, "reference_z_m: %g m is not between the tank window and the barrier or winding",
                 s->reference_z_m);
        return -1;
    }
    if (s->core_y_min_m >= s->core_y_max_m) {
        snprintf(err, errlen, "core_y_min_m: must be below core_y_max_m");
        return -1;
    }
    if (s->barrier_y_min_m >= s->barrier_y_max_m) {
        snprintf(err, errlen, "barrier_y_min_m: must be below barrier_y_max_m");
        return -1;
    }
    if (s->clutter && s->far_wall &&
        s->far_wall_z_m <=
            s->face_z_m + (s->mode == SIM_MODE_3D ? 2 * s->outer_radius_m : s->radial_build_m)) {
        snprintf(err, errlen, "far_wall_z_m: %g m is not behind the winding", s->far_wall_z_m);
        return -1;
    }
    if (isnan(s->target_z_near_m) != isnan(s->target_z_far_m)) {
        snprintf(err, errlen, "target_z_near_m, target_z_far_m: give both or neither");
        return -1;
    }
    if (!isnan(s->target_z_near_m) && s->target_z_near_m >= s->target_z_far_m) {
        snprintf(err, errlen, "target_z_near_m: must be below target_z_far_m");
        return -1;
    }
    if (s->pulse == SIM_PULSE_FILE && s->pulse_file[0] == '\0') {
        snprintf(err, errlen, "pulse_file: required when pulse is file");
        return -1;
    }
    double nyquist = 0.5 / s->sample_interval_s;
    if (s->pulse != SIM_PULSE_FILE && 3.0 * s->centre_frequency_hz > nyquist) {
        snprintf(err, errlen, "sample_interval_s: %g s is too coarse for a %g Hz pulse (Nyquist %g Hz)",
                 s->sample_interval_s, s->centre_frequency_hz, nyquist);
        return -1;
    }
    if (validate_fronts(s, err, errlen) != 0)
        return -1;
    if (s->tilt_deg != 0 && s->mode == SIM_MODE_2D && fmod(fabs(s->tilt_azimuth_deg), 180.0) != 0) {
        snprintf(err, errlen, "tilt_azimuth_deg: in 2d mode the tilt must lie in the y-z plane (0 or 180)");
        return -1;
    }
    return 0;
}
