/* The simulated scene: winding, medium, clutter, antennas, digitiser and
 * positions. Every quantity is a named parameter in ONE table (scene.c); the
 * CLI options, the JSON scene files, --help and the README's parameter list
 * are all driven by that table so they cannot drift apart.
 *
 * Units are SI throughout (m, s, Hz, V); angles in degrees. Names carry the
 * unit as a suffix where there is one. */
#ifndef UWBSIM_SCENE_H
#define UWBSIM_SCENE_H

#include <stddef.h>
#include <stdio.h>

enum sim_mode { SIM_MODE_3D = 0, SIM_MODE_2D = 1 };
enum sim_polarisation { SIM_POL_PARALLEL = 0, SIM_POL_PERPENDICULAR = 1 };
enum sim_pulse_kind { SIM_PULSE_RICKER = 0, SIM_PULSE_MONOCYCLE = 1, SIM_PULSE_FILE = 2 };

#define SIM_TEXT_MAX 512
#define SIM_DISKS_MAX 500

struct sim_scene {
    /* general */
    int mode;                       /* enum sim_mode */
    char description[SIM_TEXT_MAX]; /* free text; goes to the truth file only */
    double element_size_m;          /* 0: automatic */
    int edge_diffraction;           /* PTD fringe correction at the stack's corners */

    /* medium and tank wall */
    double eps_r;
    double window_thickness_m;
    double window_eps_r;
    double window_gap_m;
    int window_echo;

    /* winding */
    int disks;
    double disk_height_m;
    double gap_m;
    double gap_eps_r; /* 0: same as the medium (oil-filled) */
    double outer_radius_m;
    double radial_build_m;
    double face_z_m;
    double bottom_y_m;
    double displacement_m;
    double height_change_m;
    double tilt_deg;
    double tilt_azimuth_deg;
    /* Radial changes of the disks' front faces, + toward the antennas (a
     * bulge: the front's range z, which grows away from the antennas, gets
     * smaller), - away from them (a dent); the back face stays.
     * radial_m: "I-J:METRES" or "I:METRES", comma-separated, disks 1..disks
     * from the bottom, a later entry winning; "" = none. face_tilt_m: the
     * top disk's front this much nearer than the bottom disk's, linear over
     * the disks between, added to radial_m. sim_scene_disk_fronts() gives
     * each disk's offset. */
    char radial_m[SIM_TEXT_MAX];
    double face_tilt_m;

    /* static clutter */
    int clutter; /* master switch */
    int core;
    double core_front_m;
    double core_width_m;
    double core_y_min_m, core_y_max_m;
    int barrier;
    double barrier_gap_m;
    double barrier_thickness_m;
    double barrier_eps_r;
    double barrier_y_min_m, barrier_y_max_m;
    int clamp;
    double clamp_y_m;
    double clamp_thickness_m;
    double clamp_width_m;
    double clamp_depth_m;
    double clamp_setback_m;
    int reference; /* the rig's fixed reference target */
    double reference_y_m;
    double reference_z_m;
    double reference_height_m;
    double reference_width_m;
    int far_wall;
    double far_wall_z_m;
    double far_wall_reflectivity;

    /* antennas and pulse */
    double tx_dy_m, tx_dz_m;
    double rx_dy_m, rx_dz_m;
    double beamwidth_deg; /* 0: isotropic */
    int polarisation;     /* enum sim_polarisation: E relative to the disk edges */
    int pulse;            /* enum sim_pulse_kind */
    char pulse_file[SIM_TEXT_MAX];
    double centre_frequency_hz;
    double pulse_derivative;
    double pulse_amplitude;
    double coupling_gain;

    /* digitiser */
    double sample_interval_s;
    int samples;
    double t0_s;
    int adc_bits;
    double adc_full_scale_v;
    int stack;
    int noise;
    double snr_db;
    double noise_bandwidth_hz; /* 0: white up to Nyquist */
    double jitter_s;
    double drift_db;

    /* positions */
    int positions;
    double position_step_m;
    double first_position_m;

    /* header (configuration, never truth) */
    double target_z_near_m; /* NaN: absent */
    double target_z_far_m;
    char created[SIM_TEXT_MAX]; /* "": absent */
    char scan_id[SIM_TEXT_MAX];
    char comment[SIM_TEXT_MAX];
};

enum sim_param_type {
    SIM_PARAM_NUMBER,    /* double */
    SIM_PARAM_OPTNUMBER, /* double, NaN when absent ("none" / JSON null) */
    SIM_PARAM_INT,
    SIM_PARAM_BOOL,  /* int 0/1 */
    SIM_PARAM_ENUM,  /* int index into choices */
    SIM_PARAM_STRING /* char[SIM_TEXT_MAX] */
};

struct sim_param {
    const char *name; /* JSON key; CLI option --name with '_' written '-' */
    enum sim_param_type type;
    const char *unit; /* "" when dimensionless */
    const char *def;  /* default, as the text the setter accepts */
    const char *group;
    const char *help;
    size_t offset;              /* into struct sim_scene */
    double min, max;            /* inclusive limits for numbers and integers */
    const char *const *choices; /* ENUM: NULL-terminated */
    /* STRING: checks the text's syntax when set (NULL: any text) */
    int (*check)(const char *value, char *err, size_t errlen);
};

/* The table, in --help order, and its length. */
const struct sim_param *sim_params(size_t *count);
/* Look up by JSON key or CLI spelling (dashes accepted). NULL if unknown. */
const struct sim_param *sim_param_find(const char *key);

/* Every parameter at its default. Returns 0 (-1 only if the table is broken). */
int sim_scene_default(struct sim_scene *scene);
/* Set one parameter from text (the CLI's way). err: "KEY: problem". */
int sim_scene_set(struct sim_scene *scene, const char *key, const char *value, char *err, size_t errlen);
/* The current value as text that sim_scene_set accepts back. */
void sim_scene_get(const struct sim_scene *scene, const struct sim_param *p, char *buf, size_t buflen);
/* Checks between parameters (a height change that would close the gaps, a
 * build thicker than the radius...). err names the parameters involved. */
int sim_scene_validate(const struct sim_scene *scene, char *err, size_t errlen);

/* JSON scene files: one flat object whose keys are parameter names.
 * Unknown keys and wrongly typed values are rejected, naming the key.
 * Keys not in the file keep their current value in *scene. */
int sim_scene_load_json(const char *path, struct sim_scene *scene, char *err, size_t errlen);
int sim_scene_apply_json_text(const char *text, const char *name, struct sim_scene *scene, char *err,
                              size_t errlen);
/* The whole scene as a JSON object text (malloc'd), loadable again. */
int sim_scene_to_json(const struct sim_scene *scene, char **json);

/* Documentation from the table: the --help option list and a Markdown table. */
void sim_scene_print_help(FILE *out);
void sim_scene_print_markdown(FILE *out);

/* Derived geometry used by the engine and the truth file. */
double sim_scene_pitch_m(const struct sim_scene *scene); /* disk + gap after height change */
double sim_scene_gap_actual_m(const struct sim_scene *scene);
double sim_scene_stack_height_m(const struct sim_scene *scene);
double sim_scene_nominal_center_y_m(const struct sim_scene *scene);
double sim_scene_antenna_y_m(const struct sim_scene *scene, int position);

/* Each disk's front offset in m (+ toward the antennas), bottom disk first,
 * from radial_m and face_tilt_m: front[0 .. disks-1]. err names the
 * parameter and the problem (a disk the winding does not have). */
int sim_scene_disk_fronts(const struct sim_scene *scene, double *front, char *err, size_t errlen);
/* The same from radial_m alone (face_tilt_m left out). */
int sim_scene_radial_changes(const struct sim_scene *scene, double *front, char *err, size_t errlen);
/* Set the radial change of disks from..to (1-based, bottom first) to metres,
 * keeping the other disks' changes; radial_m is rewritten as runs of equal
 * offsets ("2-4:0.006,6:-0.002"). The scene is unchanged on error. */
int sim_scene_set_radial(struct sim_scene *scene, int from, int to, double metres, char *err, size_t errlen);
/* radial_m's syntax (the table's check; the disks' count is validate's). */
int sim_radial_check(const char *value, char *err, size_t errlen);

#endif
