/* The face's range along the height, baseline against this scan: a radial
 * change of the winding (a disk buckled toward the tank or in toward the
 * core) moves the face's echo in range at those heights only.
 *
 * Why relative to a line: the whole face's range moves with the oil's
 * wave speed (its temperature), and a winding leaning in its clamps moves
 * it linearly with height; neither is a buckle. The line is fitted to the
 * rows that did not change (robustly, the changed rows left out in turn),
 * its slope is reported as the tilt, and the change is what stands off it.
 *
 * Why a share of the baseline's own ripple in that line: the face's range
 * ripples along the height by about a millimetre, and in the tank most of
 * that ripple stays where it is in the image as the winding moves (the
 * tank's fixed scene puts it there: tools/uwbsim's winding without its
 * clutter has none, with it a share of 0.6 on a 16 mm shift), so a row
 * compared with the baseline's row at the same height of the winding
 * reads the ripple's difference over the shift: -1.5 mm on a 30 mm shift
 * of the full-wave tank. In the family's and
 * the paper's scenes it moves with the winding instead. The share is
 * fitted with the line, on the rows that did not change, between 0 (all
 * moves with the winding) and 1 (all stays in the image).
 *
 * Why the tilt is the unchanged rows' own slope, the share's ripple left
 * in it: the share is fitted on the ripple's short stretches, and the
 * ripple's rise over the face (the image's range bowing toward the face's
 * ends, read over the shift) moves with the winding even where they stay:
 * taking the share of it out of the slope leaned the tank's +30 mm shift
 * by 1.96 mm and two fresh draws' by 0.08-0.09 mm per mm moved, and over
 * the 33 full-wave pure shifts of 4 mm or more the rms lean per mm moved
 * is 0.037 with it out, 0.025 with it in.
 *
 * Why the mean over the changed span for the size: the antennas see the
 * whole face at once, so the image's range at the edge of a bulge leans
 * toward its neighbours and a narrow ridge overshoots; the mean over the
 * rows past half the largest change reads the bulge's own offset. */
#include "uwb/radial.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Passes of the line fit, each leaving out the rows standing off the last
 * line by more than half the watch limit. */
#define LINE_PASSES 4
/* A row's range is read only where the face's echo is at least this
 * fraction of the profile's peak in both scans (the edges' own fraction). */
#define ROW_FRACTION 0.5
/* 1-sigma of the tilt per metre of the axial shift compared at: the face
 * moving through the image's height-dependent range bias (the aperture's
 * view and the tank's fixed scene) changes its image's range along the
 * height in proportion to the move, and the linear part of that change
 * cannot be told from a lean, nor does it show in the rows' scatter about
 * the line. The rms of tilt over shift on the 33 full-wave pure shifts of
 * 4 mm or more (tank, family, paper, fresh draws: 0 to 0.055) is 0.025. */
#define TILT_PER_SHIFT 0.03
/* 1-sigma of a change's size from the imaging's blur, as a fraction of it:
 * over a few disks the shared tank's four full-wave radial scans read -22 %
 * to +21 %; a change narrower than two of the image's resolution cells (a
 * single disk) is blurred into its neighbours and reads short, 61-63 % of a
 * single disk's bulge in 2-D physical optics (tools/uwbsim). */
#define SIZE_FRACTION 0.12
/* 1-sigma of a lean's tilt from the same blur and from a barrier near the
 * face, as a fraction of it. A pressboard barrier within half a wavelength
 * in front of the face returns the face's echo to it, and that multiple
 * moves twice as far as the face: the peak between them reads a change
 * in range long. Over the fifteen full-wave leans of the fresh draws
 * (tools/fdtd/draw_deformed.py: 2.9-6.9 mm) the reading runs 11 % short to
 * 43 % long, the two longest with the barrier 0.39 and 0.41 wavelengths
 * in front (s108, s103: +8.59 for +6.68; without its barrier the same
 * lean read +7.04); the smallest share that puts all fifteen within
 * 2 sigma is 0.085 (s103; 0.048 was the six first drawn). */
#define TILT_FRACTION 0.09
/* The share of the baseline's ripple is fitted between 0 and 1 (the
 * line's frame_share): where the rows cannot pin it, its 1-sigma is taken
 * as no more than half that range (a 95 % interval as wide as the whole).
 * Over a shift of a few millimetres the ripple's difference can be nearly
 * a straight line, which leaves the share unpinned (least-squares sigma
 * 9.7 on fresh s113's 6 mm lean, read at -1.6 mm): unbounded, the slope's
 * sigma grew to 1.78 mm from a share that cannot move the slope by more
 * than 0.09 mm. */
#define SHARE_SIGMA_MAX 0.5
#define NARROW_SIZE_FRACTION 0.35
#define NARROW_CELLS 2.0
/* ...and between NARROW_CELLS and one cell more the fraction ramps from
 * the narrow one to SIZE_FRACTION, so that sigma does not jump on a row of
 * the change's width: fresh s102's single disk bulged 4 mm spans 2.18
 * cells at half its size and reads +2.39 (60 %), 2.4 sigma off at 0.12. */

/* A profile's value at y (linear between rows); NAN outside. */
static double value_at(const struct uwb_face_profile *p, double y)
{
    double x = (y - p->y0_m) / p->dy_m;
    int i = (int)floor(x);
    if (!p->value || i < 0 || i + 1 >= p->n)
        return NAN;
    double t = x - i;
    return (1.0 - t) * p->value[i] + t * p->value[i + 1];
}

double uwb_radial_frame_ripple(const struct uwb_face_profile *baseline_range, double y_m, double shift_m)
{
    double d = value_at(baseline_range, y_m) - value_at(baseline_range, y_m + shift_m);
    return isfinite(d) ? d : 0.0;
}

static double profile_peak(const struct uwb_face_profile *p, double lo_m, double hi_m)
{
    double peak = 0.0;
    for (int i = 0; i < p->n; i++) {
        double y = p->y0_m + i * p->dy_m;
        if (y >= lo_m && y <= hi_m && p->value[i] > peak)
            peak = p->value[i];
    }
    return peak;
}

/* The line's reference at row i: its level and slope, and its share of
 * the baseline's ripple over the shift. */
static double line_reference(const struct uwb_radial *r, const struct uwb_radial_line *l,
                             const struct uwb_face_profile *rb, int i)
{
    double y = r->y0_m + i * r->dy_m;
    return uwb_radial_line_at(l, y) + l->frame_share * uwb_radial_frame_ripple(rb, y, r->figures.shift_m);
}

/* Least squares over the rows `use` marks of offset = level + slope (y -
 * mid) + share ripple (slope 0 without with_slope), the share held to
 * 0..1 (the ripple's part left after level and slope, regressed; then
 * level and slope without it); 0, or -1 with fewer than 3 rows. */
static int fit_line(const struct uwb_radial *r, const double *offset, const struct uwb_face_profile *rb,
                    const unsigned char *use, int with_slope, struct uwb_radial_line *l)
{
    double n = 0, sy = 0, so = 0, sr = 0;
    for (int i = 0; i < r->n; i++)
        if (use[i]) {
            n += 1;
            sy += r->y0_m + i * r->dy_m;
            so += offset[i];
            sr += uwb_radial_frame_ripple(rb, r->y0_m + i * r->dy_m, r->figures.shift_m);
        }
    if (n < 3)
        return -1;
    l->y_mid_m = sy / n;
    double syy = 0, syo = 0, syr = 0;
    for (int i = 0; i < r->n; i++)
        if (use[i]) {
            double dy = r->y0_m + i * r->dy_m - l->y_mid_m;
            syy += dy * dy;
            syo += dy * offset[i];
            syr += dy * uwb_radial_frame_ripple(rb, r->y0_m + i * r->dy_m, r->figures.shift_m);
        }
    double slope_o = with_slope && syy > 0.0 ? syo / syy : 0.0;
    double slope_r = with_slope && syy > 0.0 ? syr / syy : 0.0;
    double cross = 0, ripple2 = 0;
    for (int i = 0; i < r->n; i++)
        if (use[i]) {
            double y = r->y0_m + i * r->dy_m, dy = y - l->y_mid_m;
            double eo = offset[i] - so / n - slope_o * dy;
            double er = uwb_radial_frame_ripple(rb, y, r->figures.shift_m) - sr / n - slope_r * dy;
            cross += eo * er;
            ripple2 += er * er;
        }
    l->frame_share = ripple2 > 0.0 ? fmin(1.0, fmax(0.0, cross / ripple2)) : 0.0;
    l->level_m = (so - l->frame_share * sr) / n;
    l->slope = slope_o - l->frame_share * slope_r;
    l->lean_slope = slope_o;
    return 0;
}

/* The line through the rows that did not change: from the level most
 * rows agree with, LINE_PASSES fits each leaving out the rows standing
 * off the last by more than half the watch limit; use gets the rows of
 * the last. 0, or -1 when fewer than 3 rows are left. */
static int fit_reference(const struct uwb_radial *r, const double *offset, const struct uwb_face_profile *rb,
                         const unsigned char *readable, double level, double y_mid_m, double watch_m,
                         int with_slope, unsigned char *use, struct uwb_radial_line *line)
{
    *line = (struct uwb_radial_line){.level_m = level, .slope = 0.0, .y_mid_m = y_mid_m};
    for (int pass = 0; pass < LINE_PASSES; pass++) {
        for (int i = 0; i < r->n; i++)
            use[i] = readable[i] && fabs(offset[i] - line_reference(r, line, rb, i)) <= 0.5 * watch_m;
        if (fit_line(r, offset, rb, use, with_slope, line) != 0)
            return -1;
    }
    return 0;
}

/* Whether the largest change off the line is past the watch limit with
 * unchanged rows on one side of it only (it reaches the face's end). */
static int change_one_sided(const struct uwb_radial *r, const double *offset,
                            const struct uwb_face_profile *rb, const unsigned char *readable,
                            const unsigned char *use, const struct uwb_radial_line *line, double watch_m)
{
    int at = -1;
    double largest = 0.0;
    for (int i = 0; i < r->n; i++) {
        double change = fabs(offset[i] - line_reference(r, line, rb, i));
        if (readable[i] && change > largest) {
            largest = change;
            at = i;
        }
    }
    if (at < 0 || largest <= watch_m)
        return 0;
    int below = 0, above = 0;
    for (int i = 0; i < r->n; i++) {
        if (!use[i])
            continue;
        below |= i < at;
        above |= i > at;
    }
    return !(below && above);
}

/* The readable rows about row `at` whose change has the sign of the
 * largest (at's) and at least `fraction` of its size: *from..*to. */
static void same_sign_span(const struct uwb_radial *r, const unsigned char *readable, int at, double fraction,
                           int *from, int *to)
{
    double largest = r->change_m[at], least = fraction * largest * largest;
    int f = at, t = at;
    while (f > 0 && readable[f - 1] && r->change_m[f - 1] * largest > 0 &&
           r->change_m[f - 1] * largest >= least)
        f--;
    while (t < r->n - 1 && readable[t + 1] && r->change_m[t + 1] * largest > 0 &&
           r->change_m[t + 1] * largest >= least)
        t++;
    *from = f;
    *to = t;
}

/* Range noise of one row's face: the envelope's peak moves by about its
 * half-width, a quarter wavelength, times noise over signal. */
static double row_noise_m(const struct uwb_analysis *a, double noise_rms, double y)
{
    double image_noise = noise_rms * sqrt((double)(a->measured.positions > 0 ? a->measured.positions : 1));
    double e = value_at(&a->profile, y);
    return e > 0.0 ? image_noise / e * a->wavelength_m / 4.0 : INFINITY;
}

/* 1-sigma of the lean's slope, m of range per m of height, from its fit:
 * the scatter of its rows about the line (what the imaging leaves of a
 * pure shift), through the level, the slope and the share of the ripple
 * fitted together, and the scans' noise, each row's, carried into the
 * least-squares slope. The lean keeps the share's ripple in it, yet how
 * much of the ripple's rise is the image's and not the winding's is known
 * only as well as the share: where the faces are compared at a shift the
 * winding did not make (a bulge read in part as a movement), the rise
 * stays in the image and reads as a lean. Rows within a quarter
 * wavelength share their noise and their ripple, so the slope gains only
 * over independent stretches of correlated_rows. */
static double slope_uncertainty(const struct uwb_radial *r, const struct uwb_analysis *cur,
                                const struct uwb_analysis *base, const unsigned char *use,
                                const struct uwb_radial_line *l, double correlated_rows, double noise_rms)
{
    double n = 0, syy = 0, scatter = 0, noise = 0, sr = 0, syr = 0;
    for (int i = 0; i < r->n; i++)
        if (use[i]) {
            double y = r->y0_m + i * r->dy_m, dy = y - l->y_mid_m;
            double row =
                hypot(row_noise_m(base, noise_rms, y), row_noise_m(cur, noise_rms, y + r->figures.shift_m));
            n += 1;
            syy += dy * dy;
            scatter += r->change_m[i] * r->change_m[i];
            noise += dy * dy * row * row;
            double ripple = uwb_radial_frame_ripple(&base->face_range, y, r->figures.shift_m);
            sr += ripple;
            syr += dy * ripple;
        }
    if (n < 3 || syy <= 0.0)
        return INFINITY;
    double ripple2 = 0;
    for (int i = 0; i < r->n; i++)
        if (use[i]) {
            double y = r->y0_m + i * r->dy_m, dy = y - l->y_mid_m;
            double er =
                uwb_radial_frame_ripple(&base->face_range, y, r->figures.shift_m) - sr / n - syr / syy * dy;
            ripple2 += er * er;
        }
    double s2 = scatter / n;
    double slope_per_share = syr / syy;
    double share_var = SHARE_SIGMA_MAX * SHARE_SIGMA_MAX;
    if (ripple2 > 0.0)
        share_var = fmin(share_var, s2 * correlated_rows / ripple2);
    double fit = s2 * correlated_rows / syy + slope_per_share * slope_per_share * share_var;
    return sqrt(fit + correlated_rows * noise / (syy * syy));
}

/* How many readable rows agree with `value` (within half the watch limit). */
static int rows_agreeing(const struct uwb_radial *r, const double *offset, const unsigned char *readable,
                         double value, double watch_m)
{
    int count = 0;
    for (int j = 0; j < r->n; j++)
        count += readable[j] && fabs(offset[j] - value) <= 0.5 * watch_m;
    return count;
}

/* Where the rows that stand off `level` by more than half the watch limit
 * gather: the offset most of them agree with (within half the watch
 * limit), and how many do (0 when none stand off). */
static int other_level(const struct uwb_radial *r, const double *offset, const unsigned char *readable,
                       double level, double watch_m, double *other)
{
    int best_count = 0;
    for (int i = 0; i < r->n; i++) {
        if (!readable[i] || fabs(offset[i] - level) <= 0.5 * watch_m)
            continue;
        int count = 0;
        for (int j = 0; j < r->n; j++)
            count += readable[j] && fabs(offset[j] - level) > 0.5 * watch_m &&
                     fabs(offset[j] - offset[i]) <= 0.5 * watch_m;
        if (count > best_count) {
            best_count = count;
            *other = offset[i];
        }
    }
    return best_count;
}

/* The offset nearest `target` that at least `least_rows` readable rows
 * agree with (within half the watch limit): 1 and *level, or 0 when no
 * offset has so many. */
static int level_nearest(const struct uwb_radial *r, const double *offset, const unsigned char *readable,
                         double target, double watch_m, double least_rows, double *level)
{
    int found = 0;
    for (int i = 0; i < r->n; i++) {
        if (!readable[i] || (found && fabs(offset[i] - target) >= fabs(*level - target)))
            continue;
        if (rows_agreeing(r, offset, readable, offset[i], watch_m) >= least_rows) {
            found = 1;
            *level = offset[i];
        }
    }
    return found;
}

/* The line's rows more than `guard` rows clear of from..to. */
static int rows_clear_of(const struct uwb_radial *r, const unsigned char *use, int from, int to, int guard)
{
    int clear = 0;
    for (int i = 0; i < r->n; i++)
        clear += (i < from - guard || i > to + guard) && use[i];
    return clear;
}

/* A change's blur reaches past its rows by about the image's range
 * resolution (a quarter wavelength), and the unchanged rows beside it
 * carry its flank into the line: disks 4-6 of 7 bulged 4 mm leave one disk
 * above, read +2 to +1 mm, and lean the line +2.26 mm (fresh s106). How
 * far the rows clear of the change by that much lean off the line (the
 * slope of their changes, r->change_m, already off the line) is a term of
 * the tilt's sigma; with no clear rows on one side no lean can be told
 * from the flank, and the term is the whole tilt (a level line's none). */
static void tilt_clear_of_change(struct uwb_radial *r, const struct uwb_face_profile *rb,
                                 const unsigned char *use, int from, int to, double correlated_rows,
                                 double height_m)
{
    struct uwb_radial_verdict *fig = &r->figures;
    unsigned char clear[UWB_RADIAL_MAX_ROWS];
    int guard = (int)ceil(correlated_rows), below = 0, above = 0;
    for (int i = 0; i < r->n; i++) {
        int beyond = i < from - guard || i > to + guard;
        clear[i] = beyond && use[i];
        if (clear[i]) {
            below += i < from;
            above += i > to;
        }
    }
    struct uwb_radial_line clear_line;
    double parted = below > 0 && above > 0 && fit_line(r, r->change_m, rb, clear, 1, &clear_line) == 0
                        ? clear_line.lean_slope
                        : fig->line.lean_slope;
    fig->tilt_uncertainty_m = hypot(fig->tilt_uncertainty_m, parted * height_m);
}

int uwb_radial_measure(const struct uwb_analysis *cur, const struct uwb_analysis *base, double shift_m,
                       double watch_m, double noise_rms, struct uwb_radial *r)
{
    return uwb_radial_measure_referenced(cur, base, shift_m, watch_m, noise_rms, NULL, r);
}

int uwb_radial_measure_referenced(const struct uwb_analysis *cur, const struct uwb_analysis *base,
                                  double shift_m, double watch_m, double noise_rms,
                                  const struct uwb_oil_reference *oil, struct uwb_radial *r)
{
    memset(r, 0, sizeof *r);
    struct uwb_radial_verdict *fig = &r->figures;
    fig->shift_m = shift_m;
    if (!cur->edges.found || !base->edges.found || !cur->face_range.value || !base->face_range.value) {
        snprintf(fig->withheld, sizeof fig->withheld, "the face's range is not measured in both scans");
        return 0;
    }
    const struct uwb_face_profile *rb = &base->face_range;
    r->dy_m = rb->dy_m;
    double lo = base->edges.lower_m, hi = base->edges.upper_m;
    r->y0_m = rb->y0_m + ceil((lo - rb->y0_m) / rb->dy_m) * rb->dy_m;
    r->n = (int)floor((hi - r->y0_m) / r->dy_m) + 1;
    if (r->n > UWB_RADIAL_MAX_ROWS)
        r->n = UWB_RADIAL_MAX_ROWS;
    /* Where the face search found the baseline's face beside a brighter
     * reflector in its own range column (a plate's edge level with it:
     * base->face_rows_m set), the baseline's range beyond the face's ends
     * is that reflector's, not the face's ripple: the ripple over the shift
     * is then read on the face's rows only (its edges, a row either side),
     * and is no share of the line beyond them. On the 3-D tank s011 moved
     * -27.5 mm toward its lower plate it read +6.31 mm at the face's end,
     * alarm. Elsewhere the face's skirt carries its ripple past its edges
     * (the 2-D tank's +30 mm shift: +0.17 mm with it, +0.94 mm without). */
    struct uwb_face_profile on_face = *rb;
    if (base->face_rows_m[0] < base->face_rows_m[1]) {
        int first = (int)fmax(0.0, floor((lo - rb->y0_m) / rb->dy_m) - 1.0);
        int last = (int)fmin(rb->n - 1.0, ceil((hi - rb->y0_m) / rb->dy_m) + 1.0);
        on_face.y0_m = rb->y0_m + first * rb->dy_m;
        on_face.value = rb->value + first;
        on_face.n = last >= first ? last - first + 1 : 0;
    }
    const struct uwb_face_profile *ripple_rows = &on_face;
    double peak_b = profile_peak(&base->profile, lo, hi);
    double peak_c = profile_peak(&cur->profile, lo + shift_m, hi + shift_m);
    /* change_m holds each row's offset until the line is taken out of it:
     * no second row array on the stack. */
    double *offset = r->change_m;
    unsigned char readable[UWB_RADIAL_MAX_ROWS], use[UWB_RADIAL_MAX_ROWS];
    int rows = 0;
    for (int i = 0; i < r->n; i++) {
        double y = r->y0_m + i * r->dy_m;
        double zb = value_at(rb, y), zc = value_at(&cur->face_range, y + shift_m);
        double eb = value_at(&base->profile, y), ec = value_at(&cur->profile, y + shift_m);
        readable[i] =
            isfinite(zb) && isfinite(zc) && eb >= ROW_FRACTION * peak_b && ec >= ROW_FRACTION * peak_c;
        offset[i] = readable[i] ? zb - zc : 0.0; /* + : nearer the antenna now */
        use[i] = readable[i];
        rows += readable[i];
    }
    if (rows < 3) {
        memset(r->change_m, 0, sizeof r->change_m); /* offsets, no change */
        snprintf(fig->withheld, sizeof fig->withheld,
                 "too few rows of the face are bright enough in both scans");
        return 0;
    }
    /* The first line: level at the offset most rows agree with (within
     * half the watch limit), which a change over fewer rows than the rest
     * does not move. A median would fall between two groups of rows (a
     * bulge over half the face) and the next pass would fit its flank. */
    int best_count = -1;
    double level = 0.0;
    for (int i = 0; i < r->n; i++) {
        if (!readable[i])
            continue;
        int count = rows_agreeing(r, offset, readable, offset[i], watch_m);
        if (count > best_count) {
            best_count = count;
            level = offset[i];
        }
    }
    /* A change over half the face gathers as many rows as the unchanged
     * rest: the oil's own offset, read from the static scene, says which
     * of the two levels did not move, where it can tell them apart. */
    double other = 0.0;
    if (oil && oil->measured && other_level(r, offset, readable, level, watch_m, &other) >= 3 &&
        fabs(other - level) > 4.0 * oil->sigma_m &&
        fabs(other - oil->face_offset_m) < fabs(level - oil->face_offset_m))
        level = other;
    /* ...and a change's blurred flanks never lie flat, so neither of the
     * two most agreed offsets need be the rows that did not move (a dent
     * over half the face in air: the dent's floor and its flank, -5.7 and
     * -3.3 mm, the oil's offset -0.2 mm, +3.6 mm read at the wrong end).
     * Where the oil still tells the level from its offset, the level is the
     * offset nearest it that a stretch of the face agrees with (a quarter
     * wavelength of rows, at least 3). */
    double correlated_rows = fmax(1.0, base->wavelength_m / 4.0 / r->dy_m);
    double nearest = 0.0;
    if (oil && oil->measured && fabs(level - oil->face_offset_m) > fmax(4.0 * oil->sigma_m, 0.5 * watch_m) &&
        level_nearest(r, offset, readable, oil->face_offset_m, watch_m, fmax(3.0, correlated_rows),
                      &nearest) &&
        fabs(nearest - oil->face_offset_m) < fabs(level - oil->face_offset_m))
        level = nearest;
    /* A change that reaches the face's end leaves unchanged rows on one
     * side of it only, and its own blur leans them (the flanks of a change
     * in the middle of the face stand off it by about a tenth of it, the
     * other way, on both sides, where their leans cancel): a slope through
     * them, carried over the change, is that blur's, not the face's. The
     * line is then level (no tilt is given); how far the sloped one would read the change is
     * a term of its sigma. */
    struct uwb_radial_line line;
    int fitted =
        fit_reference(r, offset, ripple_rows, readable, level, 0.5 * (lo + hi), watch_m, 1, use, &line) == 0;
    struct uwb_radial_line sloped = line;
    int one_sided = fitted && change_one_sided(r, offset, ripple_rows, readable, use, &line, watch_m);
    if (one_sided)
        fitted = fit_reference(r, offset, ripple_rows, readable, level, 0.5 * (lo + hi), watch_m, 0, use,
                               &line) == 0;
    if (!fitted) {
        memset(r->change_m, 0, sizeof r->change_m);
        snprintf(fig->withheld, sizeof fig->withheld,
                 "no part of the face stayed where it was: the change cannot be told from a tilt");
        return 0;
    }
    fig->measured = 1;
    fig->line = line;
    fig->tilt_m = line.lean_slope * (hi - lo);
    /* The level line's 0 is no lean measured: withheld, not published as 0. */
    if (one_sided)
        snprintf(fig->tilt_withheld, sizeof fig->tilt_withheld,
                 "the change reaches the face's end: a lean cannot be told from it there");
    int at = -1;
    double model = 0.0;
    int unchanged = 0;
    for (int i = 0; i < r->n; i++) {
        r->change_m[i] =
            readable[i] ? offset[i] - line_reference(r, &line, ripple_rows, i) : 0.0; /* in place */
        if (readable[i] && (at < 0 || fabs(r->change_m[i]) > fabs(r->change_m[at])))
            at = i;
        if (use[i]) {
            model += r->change_m[i] * r->change_m[i];
            unchanged++;
        }
    }
    model = unchanged > 0 ? sqrt(model / unchanged) : 0.0;
    if (at < 0) { /* no readable row: cannot happen past the count above */
        fig->measured = 0;
        snprintf(fig->withheld, sizeof fig->withheld,
                 "too few rows of the face are bright enough in both scans");
        return 0;
    }
    /* The size: the mean over the rows around the largest past half of it. */
    int from, to;
    same_sign_span(r, readable, at, 0.5, &from, &to);
    /* Rows within a quarter wavelength share their noise (the image's range
     * resolution): the mean gains only over independent stretches, and a
     * change narrower than that is no disk's (a glint, a row the face's
     * peak jumped on): it is averaged over one such stretch. */
    if (!one_sided)
        fig->tilt_uncertainty_m =
            hypot(slope_uncertainty(r, cur, base, use, &line, correlated_rows, noise_rms) * (hi - lo),
                  TILT_PER_SHIFT * shift_m);
    while (to - from + 1 < correlated_rows &&
           ((from > 0 && readable[from - 1]) || (to < r->n - 1 && readable[to + 1]))) {
        if (from > 0 && readable[from - 1])
            from--;
        if (to - from + 1 < correlated_rows && to < r->n - 1 && readable[to + 1])
            to++;
    }
    /* The line's share of the baseline's ripple mixes two of its rows,
     * which is no noisier than one: each row's noise is the two scans'. */
    double sum = 0.0, noise2 = 0.0, lean = 0.0;
    for (int i = from; i <= to; i++) {
        double y = r->y0_m + i * r->dy_m;
        if (one_sided)
            lean += line_reference(r, &sloped, ripple_rows, i) - line_reference(r, &line, ripple_rows, i);
        double noise = hypot(row_noise_m(base, noise_rms, y), row_noise_m(cur, noise_rms, y + shift_m));
        sum += r->change_m[i];
        noise2 += noise * noise;
    }
    int width = to - from + 1;
    lean /= width; /* the sloped line's read of the change less the level one's */
    fig->max_change_m = sum / width;
    fig->at_m = r->y0_m + at * r->dy_m + shift_m;
    double independent = fmax(1.0, width / correlated_rows);
    double noise_mean = sqrt(noise2 / width) / sqrt(independent);
    /* The largest of the profile's independent stretches stands out by
     * chance by about sqrt(2 ln N) of their scatter; and the imaging's blur
     * sizes a change only so well (SIZE_FRACTION): both are what the figure
     * cannot know of itself. */
    double stretches = fmax(1.0, rows / correlated_rows);
    double look_elsewhere = stretches > 1.0 ? sqrt(2.0 * log(stretches)) : 1.0;
    fig->uncertainty_noise_m = noise_mean;
    r->uncertainty_profile_m = hypot(noise_mean, model);
    double cells = width / correlated_rows;
    double narrow = fmin(1.0, fmax(0.0, NARROW_CELLS + 1.0 - cells));
    double size = (narrow * NARROW_SIZE_FRACTION + (1.0 - narrow) * SIZE_FRACTION) * fig->max_change_m;
    fig->uncertainty_m = sqrt(noise_mean * noise_mean + model * model * look_elsewhere * look_elsewhere +
                              size * size + lean * lean);
    /* The line's rows within the change's blur: its flank lifts the line
     * toward the change, which reads short. On the full-wave changes with
     * less than a quarter wavelength of rows clear of them (the paper's
     * scene in air, 3-4 of 6 disks) the size read 34-66 % of the truth;
     * with more (every oil tank's, 2-4 of 5-8 disks) 77-129 %. */
    if (fabs(fig->max_change_m) >= watch_m &&
        rows_clear_of(r, use, from, to, (int)ceil(correlated_rows)) < correlated_rows)
        fig->change_least_m = fig->max_change_m;
    if (fabs(fig->max_change_m) > watch_m) {
        int f = at, t = at;
        while (f > 0 && readable[f - 1] && fabs(r->change_m[f - 1]) > watch_m)
            f--;
        while (t < r->n - 1 && readable[t + 1] && fabs(r->change_m[t + 1]) > watch_m)
            t++;
        if (fabs(r->change_m[at]) > watch_m) {
            fig->has_span = 1;
            fig->from_m = r->y0_m + f * r->dy_m + shift_m;
            fig->to_m = r->y0_m + t * r->dy_m + shift_m;
        }
    }
    /* Where the echo moved in range its strength moved too, which the
     * axial fit reads in part as a movement: the rows of a change past the
     * watch limit, down to a quarter of it, for a second fit without them. */
    if (fabs(fig->max_change_m) > watch_m) {
        int f, t;
        same_sign_span(r, readable, at, 0.25, &f, &t);
        r->has_excluded = 1;
        /* A change that reaches the face's end moves the end's echo, which
         * is where the axial fit reads the edge: no second fit can part the
         * two. */
        r->excluded_at_end = f == 0 || !readable[f - 1] || t == r->n - 1 || !readable[t + 1];
        r->excluded_lo_m = r->y0_m + f * r->dy_m;
        r->excluded_hi_m = r->y0_m + t * r->dy_m;
        if (!one_sided)
            tilt_clear_of_change(r, ripple_rows, use, f, t, correlated_rows, hi - lo);
    }
    /* The imaging's blur sizes a lean as it sizes a change: the face's
     * range at its ends leans toward its middle. */
    if (!fig->tilt_withheld[0])
        fig->tilt_uncertainty_m = hypot(fig->tilt_uncertainty_m, TILT_FRACTION * fig->tilt_m);
    return 0;
}
