/* Owning a struct uwb_image: allocate and free its pixels. */
#include "uwb/image.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int uwb_image_alloc(struct uwb_image *img, int ny, int nz, char *err, size_t errlen)
{
    memset(img, 0, sizeof *img);
    if (ny < 1 || nz < 1) {
        if (err && errlen)
            snprintf(err, errlen, "image: size %d x %d, both must be at least 1", ny, nz);
        return -1;
    }
    if ((uint64_t)ny * (uint64_t)nz > SIZE_MAX / sizeof *img->pix) { /* only with a 32-bit size_t */
        if (err && errlen)
            snprintf(err, errlen, "image: %d x %d pixels do not fit in memory", ny, nz);
        return -1;
    }
    img->pix = calloc((size_t)ny * (size_t)nz, sizeof *img->pix);
    if (img->pix == NULL) {
        if (err && errlen)
            snprintf(err, errlen, "image: cannot allocate %d x %d pixels: %s", ny, nz, strerror(ENOMEM));
        return -1;
    }
    img->ny = ny;
    img->nz = nz;
    return 0;
}

void uwb_image_free(struct uwb_image *img)
{
    if (img == NULL)
        return;
    free(img->pix);
    memset(img, 0, sizeof *img);
}
