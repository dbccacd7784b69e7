/* The scene's true edges, for --truth and for tests. */
#include "simulate.h"

#include <cjson/cJSON.h>

#include "surfaces.h"

void sim_truth(const struct sim_scene *s, struct sim_truth *t)
{
    double rot[3][3], origin[3];
    sim_stack_frame(s, rot, origin);
    double h = 0.5 * sim_scene_stack_height_m(s), R = s->outer_radius_m;
    /* the front generatrix's ends (lower and upper corners) and its middle */
    const double local[3][3] = {{0, -h, -R}, {0, h, -R}, {0, 0, -R}};
    double world[3][3];
    for (int p = 0; p < 3; p++)
        for (int i = 0; i < 3; i++)
            world[p][i] =
                origin[i] + rot[i][0] * local[p][0] + rot[i][1] * local[p][1] + rot[i][2] * local[p][2];
    t->y1_m = world[0][1];
    t->y2_m = world[1][1];
    t->center_m = 0.5 * (t->y1_m + t->y2_m);
    t->height_m = t->y2_m - t->y1_m;
    t->z_face_m = world[2][2];
}

/* World y of a point on disk i's front at local height y_local. */
static double front_world_y(const struct sim_scene *s, double y_local, double front)
{
    double rot[3][3], origin[3];
    sim_stack_frame(s, rot, origin);
    return origin[1] + rot[1][1] * y_local + rot[1][2] * (-s->outer_radius_m - front);
}

/* Radial changes, as the shared full-wave truth files give them: `radial`
 * (each run of disks radial_m moved alike: disks [I, J], the lower edge of
 * I and the upper edge of J in the scan's y, change_mm) and disk_front_mm
 * (every disk's offset, tilt included), plus face_tilt_mm. Nothing when no
 * front moved, so unchanged scenes keep their truth. */
static int add_radial(const struct sim_scene *s, cJSON *o)
{
    double change[SIM_DISKS_MAX], front[SIM_DISKS_MAX];
    char err[256];
    if (s->disks > SIM_DISKS_MAX || sim_scene_radial_changes(s, change, err, sizeof err) != 0 ||
        sim_scene_disk_fronts(s, front, err, sizeof err) != 0)
        return -1;
    int moved = 0;
    for (int i = 0; i < s->disks; i++)
        moved |= front[i] != 0;
    if (!moved)
        return 0;
    double h = 0.5 * sim_scene_stack_height_m(s), pitch = sim_scene_pitch_m(s);
    cJSON *runs = cJSON_AddArrayToObject(o, "radial");
    cJSON *fronts = cJSON_AddArrayToObject(o, "disk_front_mm");
    if (!runs || !fronts)
        return -1;
    for (int i = 0; i < s->disks;) {
        int j = i;
        while (j + 1 < s->disks && change[j + 1] == change[i])
            j++;
        if (change[i] != 0) {
            cJSON *run = cJSON_CreateObject();
            int disks[2] = {i + 1, j + 1};
            cJSON *pair = cJSON_CreateIntArray(disks, 2);
            if (!run || !pair || !cJSON_AddItemToObject(run, "disks", pair) ||
                !cJSON_AddItemToArray(runs, run)) {
                cJSON_Delete(pair);
                cJSON_Delete(run);
                return -1;
            }
            if (!cJSON_AddNumberToObject(run, "y_from_m", front_world_y(s, -h + i * pitch, front[i])) ||
                !cJSON_AddNumberToObject(run, "y_to_m",
                                         front_world_y(s, -h + j * pitch + s->disk_height_m, front[j])) ||
                !cJSON_AddNumberToObject(run, "change_mm", change[i] * 1000.0))
                return -1;
        }
        i = j + 1;
    }
    for (int i = 0; i < s->disks; i++) {
        cJSON *v = cJSON_CreateNumber(front[i] * 1000.0);
        if (!v || !cJSON_AddItemToArray(fronts, v)) {
            cJSON_Delete(v);
            return -1;
        }
    }
    if (s->face_tilt_m != 0 && !cJSON_AddNumberToObject(o, "face_tilt_mm", s->face_tilt_m * 1000.0))
        return -1;
    return 0;
}

int sim_truth_json(const struct sim_scene *s, char **json)
{
    struct sim_truth t;
    sim_truth(s, &t);
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return -1;
    int bad = !cJSON_AddNumberToObject(o, "y1_m", t.y1_m) || !cJSON_AddNumberToObject(o, "y2_m", t.y2_m) ||
              !cJSON_AddNumberToObject(o, "center_m", t.center_m) ||
              !cJSON_AddNumberToObject(o, "height_m", t.height_m) ||
              !cJSON_AddNumberToObject(o, "z_face_m", t.z_face_m) ||
              !cJSON_AddNumberToObject(o, "displacement_mm", s->displacement_m * 1000.0) ||
              !cJSON_AddNumberToObject(o, "height_change_mm", s->height_change_m * 1000.0) ||
              !cJSON_AddNumberToObject(o, "tilt_deg", s->tilt_deg) ||
              !cJSON_AddStringToObject(o, "scene", s->description) || add_radial(s, o) != 0;
    if (bad) {
        cJSON_Delete(o);
        return -1;
    }
    *json = cJSON_Print(o);
    cJSON_Delete(o);
    return *json ? 0 : -1;
}
