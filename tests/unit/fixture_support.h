/* Helpers shared by the imaging tests: load fixtures and their truth. */
#ifndef UWB_FIXTURE_SUPPORT_H
#define UWB_FIXTURE_SUPPORT_H

#include "uwb/image.h"
#include "uwb/scan.h"

#define FIXTURE_INTACT "tests/fixtures/fdtd2d-paper-intact.uwbscan"
#define FIXTURE_UP20 "tests/fixtures/fdtd2d-paper-up20mm.uwbscan"

struct fixture_truth {
    double y1_m, y2_m, z_face_m, displacement_mm;
};

/* Load a scan or fail the current test. */
void fixture_load_scan(const char *path, struct uwb_scan *scan);
/* Read PATH.truth.json beside a .uwbscan (replacing the extension). */
void fixture_load_truth(const char *scan_path, struct fixture_truth *truth);

/* Allocate an ny x nz image with its grid set, or fail the current test. */
void fixture_image_grid(struct uwb_image *img, int ny, int nz, double y0_m, double dy_m, double z0_m,
                        double dz_m);

#endif
