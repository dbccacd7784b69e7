/* Colour maps, and the colours that mean the same thing in every image.
 *
 * The intensity map runs dark violet -> blue -> teal -> green -> yellow,
 * in the manner of the perceptual maps (viridis, cividis). Why perceptual:
 * its CIE lightness L* rises monotonically and nearly linearly (about 14
 * to 90 in equal steps of ~9 between anchors), so a brighter colour always
 * means more intensity, equal dB steps look like equal steps, and the
 * image still reads in greyscale print or to a colour-blind eye. A rainbow
 * map, by contrast, invents bands (bright yellow in the middle) that look
 * like edges. The anchors were chosen by eye for us and checked for L*;
 * test_render asserts the monotonic lightness on a fine sampling. */
#include "output/render_internal.h"

#include <math.h>

struct anchor {
    double t;
    struct uwb_rgb c;
};

/*                                            L* of the anchor */
static const struct anchor perceptual[] = {
    {0.000, {58, 12, 82}},   /* 14 dark violet */
    {0.125, {70, 36, 112}},  /* 23 */
    {0.250, {64, 68, 136}},  /* 32 blue-violet */
    {0.375, {50, 100, 142}}, /* 41 blue */
    {0.500, {36, 130, 142}}, /* 50 teal */
    {0.625, {34, 158, 132}}, /* 59 */
    {0.750, {76, 186, 104}}, /* 68 green */
    {0.875, {156, 210, 60}}, /* 78 yellow-green */
    {1.000, {248, 230, 40}}, /* 90 yellow */
};

/* Signed amplitude: the two ends have the same lightness (~35) and so do
 * the two shoulders (~63), so neither polarity looks stronger; zero is
 * near-white. */
static const struct anchor diverging[] = {
    {0.00, {40, 78, 168}},                            /* strong negative: blue */
    {0.25, {112, 152, 216}}, {0.50, {245, 245, 245}}, /* zero */
    {0.75, {224, 128, 108}}, {1.00, {165, 22, 36}},   /* strong positive: red */
};

const struct uwb_rgb UWB_RGB_CURRENT_EDGE = {255, 255, 255};
const struct uwb_rgb UWB_RGB_BASELINE_EDGE = {255, 64, 200};
const struct uwb_rgb UWB_RGB_HALO = {0, 0, 0};

static unsigned char mix(unsigned char a, unsigned char b, double f)
{
    return (unsigned char)lround(a + (b - a) * f);
}

static struct uwb_rgb interpolate(const struct anchor *a, int n, double t)
{
    if (!(t > 0.0)) /* also catches NaN */
        return a[0].c;
    if (t >= 1.0)
        return a[n - 1].c;
    int i = 0;
    while (i < n - 2 && t > a[i + 1].t)
        i++;
    double f = (t - a[i].t) / (a[i + 1].t - a[i].t);
    struct uwb_rgb out = {mix(a[i].c.r, a[i + 1].c.r, f), mix(a[i].c.g, a[i + 1].c.g, f),
                          mix(a[i].c.b, a[i + 1].c.b, f)};
    return out;
}

struct uwb_rgb uwb_colormap_perceptual(double t)
{
    return interpolate(perceptual, (int)(sizeof perceptual / sizeof perceptual[0]), t);
}

struct uwb_rgb uwb_colormap_diverging(double t)
{
    return interpolate(diverging, (int)(sizeof diverging / sizeof diverging[0]), t);
}

static double srgb_to_linear(unsigned char v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

double uwb_rgb_lightness(struct uwb_rgb c)
{
    /* Relative luminance (Rec. 709 primaries, D65), then CIE L*. */
    double y = 0.2126 * srgb_to_linear(c.r) + 0.7152 * srgb_to_linear(c.g) + 0.0722 * srgb_to_linear(c.b);
    double f = y > 216.0 / 24389.0 ? cbrt(y) : (24389.0 / 27.0 * y + 16.0) / 116.0;
    return 116.0 * f - 16.0;
}

/* A verdict status's colour: the captions' badge, the trend's markers, the threshold zones. */
struct uwb_rgb uwb_status_colour(enum uwb_status status)
{
    switch (status) {
    case UWB_STATUS_OK: {
        struct uwb_rgb c = {30, 125, 60};
        return c;
    }
    case UWB_STATUS_WATCH: {
        struct uwb_rgb c = {205, 125, 0};
        return c;
    }
    case UWB_STATUS_ALARM: {
        struct uwb_rgb c = {195, 30, 30};
        return c;
    }
    case UWB_STATUS_EDGES: {
        struct uwb_rgb c = {60, 85, 130};
        return c;
    }
    case UWB_STATUS_INCONCLUSIVE:
    default: {
        struct uwb_rgb c = {105, 105, 105};
        return c;
    }
    }
}
