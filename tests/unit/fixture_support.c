#include "fixture_support.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

void fixture_load_scan(const char *path, struct uwb_scan *scan)
{
    char err[512];
    if (uwbscan_read_file(path, scan, err, sizeof err) != 0)
        TEST_FAIL_MESSAGE(err);
}

static double number(cJSON *root, const char *key, const char *path)
{
    cJSON *item = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!cJSON_IsNumber(item)) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s: no number '%s'", path, key);
        TEST_FAIL_MESSAGE(msg);
    }
    return item->valuedouble;
}

void fixture_load_truth(const char *scan_path, struct fixture_truth *truth)
{
    char path[512];
    snprintf(path, sizeof path, "%s", scan_path);
    char *dot = strstr(path, ".uwbscan");
    TEST_ASSERT_NOT_NULL(dot);
    snprintf(dot, sizeof path - (size_t)(dot - path), ".truth.json");
    FILE *f = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    char buf[4096];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    cJSON *root = cJSON_Parse(buf);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, path);
    truth->y1_m = number(root, "y1_m", path);
    truth->y2_m = number(root, "y2_m", path);
    truth->z_face_m = number(root, "z_face_m", path);
    truth->displacement_mm = number(root, "displacement_mm", path);
    cJSON_Delete(root);
}

void fixture_image_grid(struct uwb_image *img, int ny, int nz, double y0_m, double dy_m, double z0_m,
                        double dz_m)
{
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_image_alloc(img, ny, nz, err, sizeof err), err);
    img->y0_m = y0_m;
    img->dy_m = dy_m;
    img->z0_m = z0_m;
    img->dz_m = dz_m;
}
