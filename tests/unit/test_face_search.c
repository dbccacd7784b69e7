/* Which reflector is the winding (src/imaging/face_search.c): one whose
 * two ends fall inside the antenna travel, taller than the imaging draws a
 * point, and never the range searched's own limit, where a reflector
 * beyond it shows brightest. */
#include "fixture_support.h"
#include "unity.h"

#include <math.h>
#include <string.h>

#include "imaging/imaging_internal.h"
#include "uwb/image.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define WAVELENGTH_M 0.08 /* 2.5 GHz in oil */

/* An image 0..0.6 m high, 0.3..0.6 m in range (10 mm pixels), empty. */
static void empty_image(struct uwb_image *img)
{
    fixture_image_grid(img, 61, 31, 0.0, 0.01, 0.3, 0.01);
}

/* Adds a reflector at range z_peak, falling off over `width` in range,
 * bright from y_lo to y_hi and falling off over 20 mm beyond them. */
static void add_reflector(struct uwb_image *img, double z_peak, double width, double y_lo, double y_hi,
                          double amplitude)
{
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double y = img->y0_m + iy * img->dy_m, z = img->z0_m + iz * img->dz_m;
            double beyond = y < y_lo ? y_lo - y : (y > y_hi ? y - y_hi : 0.0);
            double along = exp(-pow(beyond / 0.02, 2));
            img->pix[(size_t)iy * img->nz + iz] +=
                (float)(amplitude * along * exp(-pow((z - z_peak) / width, 2)));
        }
}

/* A compact blob: rows 0.2..0.4 m, peak at range z_peak. */
static void blob_image(struct uwb_image *img, double z_peak, double width)
{
    empty_image(img);
    add_reflector(img, z_peak, width, 0.2, 0.4, 1.0);
}

/* The search over 0..0.6 m of travel in 30 mm steps finds the face at
 * z_m; frees the image. */
static void assert_face_found_at(struct uwb_image *img, double z_m)
{
    struct face_candidate face = {0};
    char reason[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_face_search(img, 0.0, 0.6, 0.03, WAVELENGTH_M, NULL, 0, NULL, &face, reason, sizeof reason),
        reason);
    TEST_ASSERT_DOUBLE_WITHIN(0.005, z_m, face.z_m);
    uwb_image_free(img);
}

static void test_a_compact_reflector_inside_the_range_is_found(void)
{
    struct uwb_image img;
    blob_image(&img, 0.45, 0.03);
    assert_face_found_at(&img, 0.45);
}

static void test_brightest_at_the_range_limit_is_no_reflector_of_it(void)
{
    for (int end = 0; end < 2; end++) {
        struct uwb_image img;
        /* Peaks just outside 0.3..0.6 m, narrow: inside, only the limit's
         * column is within 40 dB of the brightest. */
        blob_image(&img, end == 0 ? 0.28 : 0.62, 0.01);
        struct face_candidate face = {0};
        char reason[256] = "";
        TEST_ASSERT_EQUAL_INT(1, uwb_face_search(&img, 0.0, 0.6, 0.03, WAVELENGTH_M, NULL, 0, NULL, &face,
                                                 reason, sizeof reason));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "is the range's limit: a reflector beyond it"), reason);
        uwb_image_free(&img);
    }
}

/* A clamp plate level with the winding shows its edge: a point, nearer than
 * the face and nearly as bright. The nearest bright reflector is not the
 * winding when it is no taller than a point. */
static void test_a_plate_edge_nearer_than_the_face_is_passed_over(void)
{
    struct uwb_image img;
    blob_image(&img, 0.45, 0.03);
    add_reflector(&img, 0.35, 0.02, 0.15, 0.15, 0.8);
    assert_face_found_at(&img, 0.45);
}

/* A plate's front edge level with the face (the 3-D tanks' lower plate,
 * 5 mm in front of it) shares the face's range column and images twice as
 * bright: the column's peak is that point, and the face, separated from it
 * by a valley, is still the column's tall reflector. */
static void test_a_plate_edge_in_the_face_column_leaves_the_face_found(void)
{
    struct uwb_image img;
    empty_image(&img);
    add_reflector(&img, 0.40, 0.03, 0.25, 0.42, 0.5);
    add_reflector(&img, 0.40, 0.03, 0.12, 0.12, 1.0);
    struct face_candidate face = {0};
    char reason[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_face_search(&img, 0.0, 0.6, 0.03, WAVELENGTH_M, NULL, 0, NULL, &face, reason, sizeof reason),
        reason);
    TEST_ASSERT_DOUBLE_WITHIN(0.005, 0.40, face.z_m);
    /* The face's own ends (half its peak 17 mm beyond its bright rows, in
     * the row where it has dropped), not the plate's. */
    TEST_ASSERT_DOUBLE_WITHIN(0.011, 0.23, face.lower_m);
    TEST_ASSERT_DOUBLE_WITHIN(0.011, 0.44, face.upper_m);
    uwb_image_free(&img);
}

/* The same column with nothing but a second point beside the plate's: no
 * tall reflector, so the refusal still names the point. */
static void test_two_points_in_one_column_are_no_winding(void)
{
    struct uwb_image img;
    empty_image(&img);
    add_reflector(&img, 0.35, 0.02, 0.15, 0.15, 1.0);
    add_reflector(&img, 0.35, 0.02, 0.40, 0.40, 0.6);
    struct face_candidate face = {0};
    char reason[256] = "";
    TEST_ASSERT_EQUAL_INT(
        1, uwb_face_search(&img, 0.0, 0.6, 0.03, WAVELENGTH_M, NULL, 0, NULL, &face, reason, sizeof reason));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "at 0.350 m range, is a point"), reason);
    uwb_image_free(&img);
}

static void test_a_lone_point_is_no_winding(void)
{
    struct uwb_image img;
    empty_image(&img);
    add_reflector(&img, 0.35, 0.02, 0.15, 0.15, 1.0);
    struct face_candidate face = {0};
    char reason[256] = "";
    TEST_ASSERT_EQUAL_INT(
        1, uwb_face_search(&img, 0.0, 0.6, 0.03, WAVELENGTH_M, NULL, 0, NULL, &face, reason, sizeof reason));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "at 0.350 m range, is a point"), reason);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "a plate's edge"), reason);
    uwb_image_free(&img);
}

/* lambda / (4 sin theta) seen from the middle of the travel; from its end,
 * half the angles, twice the blur's share of them. */
static void test_point_blur_follows_the_angles_seen(void)
{
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 0.08 / (4.0 * sqrt(0.5)), uwb_point_blur_m(0.08, 0.3, 0.3, 0.0, 0.6));
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 0.08 / (2.0 * 0.6 / hypot(0.6, 0.3)),
                              uwb_point_blur_m(0.08, 0.0, 0.3, 0.0, 0.6));
    TEST_ASSERT_TRUE(uwb_point_blur_m(0.08, 0.3, 0.6, 0.0, 0.6) > uwb_point_blur_m(0.08, 0.3, 0.3, 0.0, 0.6));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_compact_reflector_inside_the_range_is_found);
    RUN_TEST(test_brightest_at_the_range_limit_is_no_reflector_of_it);
    RUN_TEST(test_a_plate_edge_nearer_than_the_face_is_passed_over);
    RUN_TEST(test_a_plate_edge_in_the_face_column_leaves_the_face_found);
    RUN_TEST(test_two_points_in_one_column_are_no_winding);
    RUN_TEST(test_a_lone_point_is_no_winding);
    RUN_TEST(test_point_blur_follows_the_angles_seen);
    return UNITY_END();
}
