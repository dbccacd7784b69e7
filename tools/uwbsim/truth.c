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
              !cJSON_AddStringToObject(o, "scene", s->description);
    if (bad) {
        cJSON_Delete(o);
        return -1;
    }
    *json = cJSON_Print(o);
    cJSON_Delete(o);
    return *json ? 0 : -1;
}
