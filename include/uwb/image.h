/* A 2-D image on a regular y-z grid (metres), as migration produces it. */
#ifndef UWB_IMAGE_H
#define UWB_IMAGE_H

#include <stddef.h>

struct uwb_image {
    int ny, nz;        /* rows along y (height), columns along z (range) */
    double y0_m, dy_m; /* y of row iy is y0_m + iy * dy_m */
    double z0_m, dz_m; /* z of column iz is z0_m + iz * dz_m */
    float *pix;        /* ny * nz values, pix[iy * nz + iz] */
};

int uwb_image_alloc(struct uwb_image *img, int ny, int nz, char *err, size_t errlen);
void uwb_image_free(struct uwb_image *img);

#endif
