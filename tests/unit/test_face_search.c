/* Which reflector is the winding (src/imaging/face_search.c): one whose
 * two ends fall inside the antenna travel, and never the range searched's
 * own limit, where a reflector beyond it shows brightest. */
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

/* An image 0..0.6 m high, 0.3..0.6 m in range (10 mm pixels), with a
 * compact blob: rows 0.2..0.4 m, peak at range z_peak, falling off over
 * `width` in range. */
static void blob_image(struct uwb_image *img, double z_peak, double width)
{
    char err[128];
    TEST_ASSERT_EQUAL_INT(0, uwb_image_alloc(img, 61, 31, err, sizeof err));
    img->y0_m = 0.0;
    img->dy_m = 0.01;
    img->z0_m = 0.3;
    img->dz_m = 0.01;
    for (int iy = 0; iy < img->ny; iy++)
        for (int iz = 0; iz < img->nz; iz++) {
            double y = img->y0_m + iy * img->dy_m, z = img->z0_m + iz * img->dz_m;
            double along = (y >= 0.2 && y <= 0.4) ? 1.0 : exp(-pow((fabs(y - 0.3) - 0.1) / 0.02, 2));
            img->pix[(size_t)iy * img->nz + iz] = (float)(along * exp(-pow((z - z_peak) / width, 2)));
        }
}

static void test_a_compact_reflector_inside_the_range_is_found(void)
{
    struct uwb_image img;
    blob_image(&img, 0.45, 0.03);
    struct face_candidate face = {0};
    char reason[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwb_face_search(&img, 0.0, 0.6, 0.03, NULL, 0, &face, reason, sizeof reason), reason);
    TEST_ASSERT_DOUBLE_WITHIN(0.005, 0.45, face.z_m);
    uwb_image_free(&img);
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
        TEST_ASSERT_EQUAL_INT(1,
                              uwb_face_search(&img, 0.0, 0.6, 0.03, NULL, 0, &face, reason, sizeof reason));
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(reason, "is the range's limit: a reflector beyond it"), reason);
        uwb_image_free(&img);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_compact_reflector_inside_the_range_is_found);
    RUN_TEST(test_brightest_at_the_range_limit_is_no_reflector_of_it);
    return UNITY_END();
}
