/* Cutting the winding and the clutter into surface elements.
 *
 * What is approximated, and why it is good enough here:
 * - E along the disk edges (polarisation parallel, the default and what a
 *   2-D TMz FDTD computes): a gap a few mm high is far below its cutoff
 *   (half a wavelength across it), nothing enters it, and the stack's outer
 *   face is one continuous metal surface. Against the FDTD fixtures this is
 *   what matches (correlation 0.9995 per trace).
 * - E across the gaps (perpendicular): the gaps are open. The outer faces of
 *   the disks are lit where they face the antennas and do not shadow each
 *   other (true for an upright stack, nearly so for small tilts). A point on
 *   a gap face at depth L (along the ray) behind the rim is lit only if the
 *   ray, entering through the gap's mouth, descends (or rises) less than the
 *   gap over L; elements straddling that limit count by the fraction lit.
 *   What travels inside the gap as a parallel-plate wave is not modelled.
 * - The winding's inner cylinder, and anything inside the stack (the core
 *   within the winding's height), is hidden. Clutter behind or beside the
 *   stack is shadowed by the stack taken as a solid cylinder (3-D) or
 *   rectangle (2-D), with a knife-edge diffraction taper at the shadow
 *   boundary instead of a hard cut (a hard cut would create spurious edge
 *   echoes that move with the antennas).
 * - The pressboard barrier is thin: one set of elements carries both its
 *   faces' reflections; rays through it get its delay and transmission.
 * - Edges: the stack's top and bottom edges (outer and inner rims) carry the
 *   PTD fringe term; corners at each gap and clutter edges are physical
 *   optics only.
 */
#include "surfaces.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define C0 299792458.0

double sim_geometry_element_size(const struct sim_scene *s)
{
    if (s->element_size_m > 0)
        return s->element_size_m;
    double lambda_min = C0 / (sqrt(s->eps_r) * 3.0 * s->centre_frequency_hz);
    return lambda_min / (s->mode == SIM_MODE_2D ? 16.0 : 8.0);
}

struct builder {
    struct sim_geometry *geo;
    const struct sim_scene *scene;
    size_t cap;
    int failed;
};

static struct sim_element *new_element(struct builder *b)
{
    struct sim_geometry *g = b->geo;
    if (b->failed)
        return NULL;
    if (g->count == b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 4096;
        struct sim_element *bigger = realloc(g->el, cap * sizeof *bigger);
        if (!bigger) {
            b->failed = 1;
            return NULL;
        }
        g->el = bigger;
        b->cap = cap;
    }
    struct sim_element *e = &g->el[g->count++];
    memset(e, 0, sizeof *e);
    return e;
}

static void rotate(const double r[3][3], const double v[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
}

void sim_geometry_to_local(const struct sim_geometry *g, const double w[3], double l[3])
{
    double d[3] = {w[0] - g->origin[0], w[1] - g->origin[1], w[2] - g->origin[2]};
    for (int i = 0; i < 3; i++) /* rot is orthonormal: inverse = transpose */
        l[i] = g->rot[0][i] * d[0] + g->rot[1][i] * d[1] + g->rot[2][i] * d[2];
}

static int inside_barrier(const struct sim_geometry *g, const double w[3])
{
    if (!g->has_barrier)
        return 0;
    if (g->mode == SIM_MODE_2D)
        return w[2] > g->barrier_front_z + 1e-9;
    return hypot(w[0], w[2] - g->barrier_axis_z) < g->barrier_outer_r - 1e-9;
}

/* A winding element given in the stack frame. */
static void add_local(struct builder *b, const double lp[3], const double ln[3], double area, double refl,
                      int kind)
{
    struct sim_element *e = new_element(b);
    if (!e)
        return;
    struct sim_geometry *g = b->geo;
    memcpy(e->lpos, lp, sizeof e->lpos);
    rotate(g->rot, lp, e->pos);
    for (int i = 0; i < 3; i++)
        e->pos[i] += g->origin[i];
    rotate(g->rot, ln, e->nrm);
    e->area = area;
    e->refl = refl;
    e->kind = (unsigned char)kind;
    e->part = SIM_PART_WINDING;
    e->behind_barrier = (unsigned char)inside_barrier(g, e->pos);
}

/* A static clutter element given in the world. */
static struct sim_element *add_world(struct builder *b, const double wp[3], const double wn[3], double area,
                                     double refl, int shadowable)
{
    struct sim_element *e = new_element(b);
    if (!e)
        return NULL;
    memcpy(e->pos, wp, sizeof e->pos);
    memcpy(e->nrm, wn, sizeof e->nrm);
    sim_geometry_to_local(b->geo, wp, e->lpos);
    e->area = area;
    e->refl = refl;
    e->kind = SIM_ELEM_PLAIN;
    e->part = SIM_PART_CLUTTER;
    e->shadowable = (unsigned char)shadowable;
    e->behind_barrier = (unsigned char)inside_barrier(b->geo, wp);
    return e;
}

static int cells(double length, double size)
{
    int n = (int)ceil(length / size - 1e-9);
    return n < 1 ? 1 : n;
}

/* Stack frame from displacement and tilt: the axis leans by tilt_deg toward
 * azimuth tilt_azimuth_deg (0 = toward the antennas, i.e. -z). */
void sim_stack_frame(const struct sim_scene *s, double rot[3][3], double origin[3])
{
    double th = s->tilt_deg * M_PI / 180.0, az = s->tilt_azimuth_deg * M_PI / 180.0;
    double d[3] = {sin(az), 0.0, -cos(az)}; /* lean direction */
    double k[3] = {d[2], 0.0, -d[0]};       /* rotation axis = y x d */
    double c = cos(th), sn = sin(th), t = 1.0 - c;
    /* Rodrigues: R = c I + sn [k]x + t k k^T */
    double K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            rot[i][j] = (i == j ? c : 0.0) + sn * K[i][j] + t * k[i] * k[j];
    origin[0] = 0.0;
    origin[1] = sim_scene_nominal_center_y_m(s) + s->displacement_m;
    origin[2] = s->face_z_m + s->outer_radius_m;
}

/* The closed face's profile along the stack's local y: each disk at its own
 * front, each gap at the farther of its two disks' fronts (the gap's mouth,
 * where both plates are), neighbours with equal fronts merged. seg holds
 * 2 disks - 1 entries; returns how many it filled. */
struct front_seg {
    double y0, y1, front;
};

static size_t front_profile(const struct sim_scene *s, const struct sim_geometry *g, struct front_seg *seg)
{
    double hd = s->disk_height_m, pitch = hd + sim_scene_gap_actual_m(s), h = g->half_height;
    size_t n = 0;
    for (int i = 0; i < s->disks; i++) {
        double yb = -h + i * pitch;
        struct front_seg piece[2] = {{yb, yb + hd, g->front[i]}, {yb + hd, yb + pitch, 0.0}};
        int pieces = 1;
        if (i < s->disks - 1) {
            piece[1].front = fmin(g->front[i], g->front[i + 1]);
            pieces = 2;
        }
        for (int k = 0; k < pieces; k++) {
            if (n > 0 && seg[n - 1].front == piece[k].front)
                seg[n - 1].y1 = piece[k].y1;
            else
                seg[n++] = piece[k];
        }
    }
    seg[0].y0 = -h; /* the stack's own ends, exactly */
    seg[n - 1].y1 = h;
    return n;
}

/* The parts of the cell [y0, y1] in each segment, as (y0, y1, front) pieces;
 * returns their count (at most 3 for a cell shorter than a disk or gap,
 * cells at most `max`). */
static int cell_pieces(const struct front_seg *seg, size_t nseg, double y0, double y1, struct front_seg *out,
                       int max)
{
    int n = 0;
    for (size_t i = 0; i < nseg && n < max; i++) {
        double a = fmax(y0, seg[i].y0), c = fmin(y1, seg[i].y1);
        if (c - a > 1e-12)
            out[n++] = (struct front_seg){a, c, seg[i].front};
    }
    return n;
}

/* The spacer between two disks: with both when they moved alike, else it
 * stays flush with the one moved less (at 0 between a bulge and a dent). */
static double spacer_front(double a, double c)
{
    if (a > 0 && c > 0)
        return fmin(a, c);
    if (a < 0 && c < 0)
        return fmax(a, c);
    return 0.0;
}

/* A horizontal face in 3-D, part of a ring: radii from rim
 * inward by width, over the angle span (2 pi: the whole ring) centred on
 * the antennas' side. Gap faces get the depth behind the mouth. */
static void add_ring(struct builder *b, double y, double up, double rim, double width, double span, int kind)
{
    struct sim_geometry *g = b->geo;
    double size = g->element_size_m;
    int nr = cells(width, size);
    double dr = width / nr;
    double ln[3] = {0.0, up, 0.0};
    for (int r = 0; r < nr; r++) {
        double d0 = r * dr, d1 = (r + 1) * dr, rad = rim - 0.5 * (d0 + d1);
        int np = cells(span * rad, size);
        double dp = span / np;
        for (int j = 0; j < np; j++) {
            double phi = -span / 2 + (j + 0.5) * dp;
            double lp[3] = {rad * sin(phi), y, -rad * cos(phi)};
            add_local(b, lp, ln, rad * dp * dr, -1.0, kind);
            if (kind != SIM_ELEM_PLAIN && !b->failed) {
                struct sim_element *e = &g->el[g->count - 1];
                e->depth0 = d0;
                e->depth1 = d1;
                e->gap = sim_scene_gap_actual_m(b->scene);
                e->mouth = rim;
            }
        }
    }
}

/* The same in 2-D: local z from zstart (the rim) backward by width. */
static void add_strip(struct builder *b, double y, double up, double zstart, double width, int kind)
{
    struct sim_geometry *g = b->geo;
    int nz = cells(width, g->element_size_m);
    double dz = width / nz;
    double ln[3] = {0.0, up, 0.0};
    for (int r = 0; r < nz; r++) {
        double lp[3] = {0.0, y, zstart + (r + 0.5) * dz};
        add_local(b, lp, ln, dz, -1.0, kind);
        if (kind != SIM_ELEM_PLAIN && !b->failed) {
            struct sim_element *e = &g->el[g->count - 1];
            e->depth0 = r * dz;
            e->depth1 = (r + 1) * dz;
            e->gap = sim_scene_gap_actual_m(b->scene);
        }
    }
}

/* A horizontal face of disk i (its top when up): in front of the gap's
 * mouth, lit as the outside; behind it, lit only through the gap. A stack
 * end is outside altogether (the whole ring in 3-D). */
static void add_disk_end(struct builder *b, int i, int up, int closed)
{
    const struct sim_scene *s = b->scene;
    struct sim_geometry *g = b->geo;
    int m2 = s->mode == SIM_MODE_2D;
    double bld = s->radial_build_m, hd = s->disk_height_m, pitch = hd + sim_scene_gap_actual_m(s);
    double yb = -g->half_height + i * pitch, y = up ? yb + hd : yb, dir = up ? 1.0 : -1.0;
    double f = g->front[i];
    int exterior = up ? (i == s->disks - 1) : (i == 0);
    if (exterior) {
        if (m2)
            add_strip(b, y, dir, g->face_local_z - f, bld + f, SIM_ELEM_PLAIN);
        else
            add_ring(b, y, dir, g->radius + f, bld + f, 2 * M_PI, SIM_ELEM_PLAIN);
        return;
    }
    if (closed)
        return; /* the gaps are shut: steps in the face are front_steps' */
    double m = fmin(f, g->front[up ? i + 1 : i - 1]);
    int kind = up ? SIM_ELEM_GAP_UP : SIM_ELEM_GAP_DOWN;
    if (m2)
        add_strip(b, y, dir, g->face_local_z - m, bld + m, kind);
    else
        add_ring(b, y, dir, g->radius + m, bld + m, M_PI, kind);
    if (f > m) { /* this disk stands out past its neighbour: the overhang is outside */
        if (m2)
            add_strip(b, y, dir, g->face_local_z - f, f - m, SIM_ELEM_PLAIN);
        else
            add_ring(b, y, dir, g->radius + f, f - m, M_PI, SIM_ELEM_PLAIN);
    }
}

/* The closed face's steps, where the profile's front changes: the part of
 * a disk's end face standing out past the gap's mouth. */
static void front_steps(struct builder *b, const struct front_seg *seg, size_t nseg)
{
    struct sim_geometry *g = b->geo;
    for (size_t i = 0; i + 1 < nseg; i++) {
        double lo = fmin(seg[i].front, seg[i + 1].front), hi = fmax(seg[i].front, seg[i + 1].front);
        double up = seg[i].front > seg[i + 1].front ? 1.0 : -1.0;
        if (g->mode == SIM_MODE_2D)
            add_strip(b, seg[i].y1, up, g->face_local_z - hi, hi - lo, SIM_ELEM_PLAIN);
        else
            add_ring(b, seg[i].y1, up, g->radius + hi, hi - lo, M_PI, SIM_ELEM_PLAIN);
    }
}

static void build_winding_3d(const struct sim_scene *s, struct builder *b, const struct front_seg *seg,
                             size_t nseg)
{
    struct sim_geometry *g = b->geo;
    double R = s->outer_radius_m, hd = s->disk_height_m;
    double gap = sim_scene_gap_actual_m(s), pitch = hd + gap, size = g->element_size_m;
    double n_oil = sqrt(s->eps_r);
    int nphi_front = cells(M_PI * R, size);
    double dphi = M_PI / nphi_front;
    int ny = cells(hd, size);

    int closed = s->polarisation == SIM_POL_PARALLEL;
    if (closed) {
        /* E along the gaps' edges: a gap of a few mm is far below its cutoff
         * (half a wavelength across it), no wave enters, and the stack's
         * outer face acts as one continuous metal cylinder (stepped where
         * disks moved radially; cells are split at the steps). */
        int nyall = cells(2 * g->half_height, size);
        double dy = 2 * g->half_height / nyall;
        for (int j = 0; j < nphi_front; j++) {
            double phi = -M_PI / 2 + (j + 0.5) * dphi;
            double ln[3] = {sin(phi), 0.0, -cos(phi)};
            for (int k = 0; k < nyall; k++) {
                struct front_seg piece[4];
                double y0 = -g->half_height + k * dy;
                int n = cell_pieces(seg, nseg, y0, y0 + dy, piece, 4);
                if (n == 1) {
                    double rf = R + piece[0].front;
                    double lp[3] = {rf * ln[0], -g->half_height + (k + 0.5) * dy, rf * ln[2]};
                    add_local(b, lp, ln, rf * dphi * dy, -1.0, SIM_ELEM_PLAIN);
                    continue;
                }
                for (int q = 0; q < n; q++) {
                    double rf = R + piece[q].front;
                    double lp[3] = {rf * ln[0], 0.5 * (piece[q].y0 + piece[q].y1), rf * ln[2]};
                    add_local(b, lp, ln, rf * dphi * (piece[q].y1 - piece[q].y0), -1.0, SIM_ELEM_PLAIN);
                }
            }
        }
        front_steps(b, seg, nseg);
    }
    for (int i = 0; i < s->disks; i++) {
        double yb = -g->half_height + i * pitch, yt = yb + hd, rf = R + g->front[i];
        /* outer face: front half (the back half never faces the antennas) */
        for (int j = 0; j < nphi_front && !closed; j++) {
            double phi = -M_PI / 2 + (j + 0.5) * dphi;
            double ln[3] = {sin(phi), 0.0, -cos(phi)};
            for (int k = 0; k < ny; k++) {
                double lp[3] = {rf * ln[0], yb + (k + 0.5) * hd / ny, rf * ln[2]};
                add_local(b, lp, ln, rf * dphi * hd / ny, -1.0, SIM_ELEM_PLAIN);
            }
        }
        /* bottom and top faces */
        add_disk_end(b, i, 0, closed);
        add_disk_end(b, i, 1, closed);
        /* a dielectric filling of the gap above this disk shows its front */
        if (!closed && i < s->disks - 1 && gap > 0 && s->gap_eps_r > 0 && s->gap_eps_r != s->eps_r) {
            double n_fill = sqrt(s->gap_eps_r);
            double refl = (n_oil - n_fill) / (n_oil + n_fill);
            double rs = R + spacer_front(g->front[i], g->front[i + 1]);
            int nyg = cells(gap, size);
            for (int j = 0; j < nphi_front; j++) {
                double phi = -M_PI / 2 + (j + 0.5) * dphi;
                double ln[3] = {sin(phi), 0.0, -cos(phi)};
                for (int k = 0; k < nyg; k++) {
                    double lp[3] = {rs * ln[0], yt + (k + 0.5) * gap / nyg, rs * ln[2]};
                    add_local(b, lp, ln, rs * dphi * gap / nyg, refl, SIM_ELEM_PLAIN);
                }
            }
        }
    }
}

static void build_winding_2d(const struct sim_scene *s, struct builder *b, const struct front_seg *seg,
                             size_t nseg)
{
    struct sim_geometry *g = b->geo;
    double zf = g->face_local_z, hd = s->disk_height_m;
    double gap = sim_scene_gap_actual_m(s), pitch = hd + gap, size = g->element_size_m;
    double n_oil = sqrt(s->eps_r);
    int ny = cells(hd, size);
    double front_n[3] = {0.0, 0.0, -1.0};
    int closed = s->polarisation == SIM_POL_PARALLEL;
    if (closed) { /* gaps below cutoff: one continuous front face (see the 3-D case) */
        int nyall = cells(2 * g->half_height, size);
        double dy = 2 * g->half_height / nyall;
        for (int k = 0; k < nyall; k++) {
            struct front_seg piece[4];
            double y0 = -g->half_height + k * dy;
            int n = cell_pieces(seg, nseg, y0, y0 + dy, piece, 4);
            if (n == 1) {
                double lp[3] = {0.0, -g->half_height + (k + 0.5) * dy, zf - piece[0].front};
                add_local(b, lp, front_n, dy, -1.0, SIM_ELEM_PLAIN);
                continue;
            }
            for (int q = 0; q < n; q++) {
                double lp[3] = {0.0, 0.5 * (piece[q].y0 + piece[q].y1), zf - piece[q].front};
                add_local(b, lp, front_n, piece[q].y1 - piece[q].y0, -1.0, SIM_ELEM_PLAIN);
            }
        }
        front_steps(b, seg, nseg);
    }

    for (int i = 0; i < s->disks; i++) {
        double yb = -g->half_height + i * pitch, yt = yb + hd, z = zf - g->front[i];
        for (int k = 0; k < ny && !closed; k++) {
            double lp[3] = {0.0, yb + (k + 0.5) * hd / ny, z};
            add_local(b, lp, front_n, hd / ny, -1.0, SIM_ELEM_PLAIN);
        }
        add_disk_end(b, i, 0, closed);
        add_disk_end(b, i, 1, closed);
        if (!closed && i < s->disks - 1 && gap > 0 && s->gap_eps_r > 0 && s->gap_eps_r != s->eps_r) {
            double n_fill = sqrt(s->gap_eps_r);
            double zs = zf - spacer_front(g->front[i], g->front[i + 1]);
            int nyg = cells(gap, size);
            for (int k = 0; k < nyg; k++) {
                double lp[3] = {0.0, yt + (k + 0.5) * gap / nyg, zs};
                add_local(b, lp, front_n, gap / nyg, (n_oil - n_fill) / (n_oil + n_fill), SIM_ELEM_PLAIN);
            }
        }
    }
}

static int add_edge(struct sim_geometry *g, size_t *cap, const double lp[3], const double lt[3],
                    const double lsa[3], const double lna[3], double wedge_n, double length)
{
    if (g->edge_count == *cap) {
        size_t n = *cap ? 2 * *cap : 256;
        struct sim_edge *bigger = realloc(g->edges, n * sizeof *bigger);
        if (!bigger)
            return -1;
        g->edges = bigger;
        *cap = n;
    }
    struct sim_edge *e = &g->edges[g->edge_count++];
    memcpy(e->lpos, lp, sizeof e->lpos);
    rotate(g->rot, lp, e->pos);
    for (int i = 0; i < 3; i++)
        e->pos[i] += g->origin[i];
    rotate(g->rot, lt, e->tangent);
    rotate(g->rot, lsa, e->s_a);
    rotate(g->rot, lna, e->n_a);
    e->wedge_n = wedge_n;
    e->length = length;
    return 0;
}

/* The stack's end faces meet its outer face (front corners in 2-D) and its
 * inner face (back corners in 2-D) in right-angle wedges, exterior angle
 * 3/2 pi; face A is the end face. Corners at each gap get no fringe term. */
static int build_edges(const struct sim_scene *s, struct sim_geometry *g)
{
    size_t cap = 0;
    double h = g->half_height, size = g->element_size_m;
    for (int top = 0; top < 2; top++) {
        double y = top ? h : -h;
        double na[3] = {0.0, top ? 1.0 : -1.0, 0.0};
        for (int inner = 0; inner < 2; inner++) {
            double sign = inner ? 1.0 : -1.0;            /* face A runs outward from an inner edge */
            double f = g->front[top ? s->disks - 1 : 0]; /* the end disk's front */
            if (s->mode == SIM_MODE_2D) {
                double lp[3] = {0.0, y, inner ? g->face_local_z + g->build : g->face_local_z - f};
                double t[3] = {1, 0, 0}, sa[3] = {0, 0, -sign};
                if (add_edge(g, &cap, lp, t, sa, na, 1.5, 1.0) != 0)
                    return -1;
                continue;
            }
            double R = inner ? g->radius - g->build : g->radius + f;
            if (R <= 0)
                continue;
            int n = cells(2 * M_PI * R, size);
            double dphi = 2 * M_PI / n;
            for (int j = 0; j < n; j++) {
                double phi = -M_PI + (j + 0.5) * dphi;
                double r[3] = {sin(phi), 0.0, -cos(phi)};
                double lp[3] = {R * r[0], y, R * r[2]};
                double t[3] = {cos(phi), 0.0, sin(phi)};
                double sa[3] = {sign * r[0], 0.0, sign * r[2]};
                if (add_edge(g, &cap, lp, t, sa, na, 1.5, R * dphi) != 0)
                    return -1;
            }
        }
    }
    return 0;
}

/* A flat rectangle in the world, normal along one axis, cut into cells:
 * spans [lo, hi] along axes u and v (u, v, w a permutation, w fixed). */
static void add_rect(struct builder *b, int u, double u0, double u1, int v, double v0, double v1, int w,
                     double wpos, int nsign, int mode2d, double refl, int shadowable)
{
    double size = b->geo->element_size_m;
    double n[3] = {0, 0, 0};
    n[w] = nsign;
    if (mode2d) { /* 2-D: objects run along x; u must be x and is dropped */
        int nv = cells(v1 - v0, size);
        for (int j = 0; j < nv; j++) {
            double p[3] = {0, 0, 0};
            p[v] = v0 + (j + 0.5) * (v1 - v0) / nv;
            p[w] = wpos;
            add_world(b, p, n, (v1 - v0) / nv, refl, shadowable);
        }
        return;
    }
    int nu = cells(u1 - u0, size), nv = cells(v1 - v0, size);
    double du = (u1 - u0) / nu, dv = (v1 - v0) / nv;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double p[3];
            p[u] = u0 + (i + 0.5) * du;
            p[v] = v0 + (j + 0.5) * dv;
            p[w] = wpos;
            add_world(b, p, n, du * dv, refl, shadowable);
        }
}

static void build_clutter(const struct sim_scene *s, struct builder *b)
{
    struct sim_geometry *g = b->geo;
    int m2 = s->mode == SIM_MODE_2D;
    double size = g->element_size_m;
    double axis_z = s->face_z_m + s->outer_radius_m; /* undisplaced winding axis */
    enum { X = 0, Y = 1, Z = 2 };

    if (s->core) {
        double w = s->core_width_m;
        add_rect(b, X, -w / 2, w / 2, Y, s->core_y_min_m, s->core_y_max_m, Z, axis_z - s->core_front_m, -1,
                 m2, -1.0, 1);
    }
    if (s->clamp) {
        double w = s->clamp_width_m, z0 = s->face_z_m + s->clamp_setback_m, z1 = z0 + s->clamp_depth_m;
        double y0 = s->clamp_y_m, y1 = y0 + s->clamp_thickness_m;
        add_rect(b, X, -w / 2, w / 2, Y, y0, y1, Z, z0, -1, m2, -1.0, 1); /* front edge face */
        add_rect(b, X, -w / 2, w / 2, Z, z0, z1, Y, y0, -1, m2, -1.0, 1); /* underside */
        add_rect(b, X, -w / 2, w / 2, Z, z0, z1, Y, y1, +1, m2, -1.0, 1); /* top */
    }
    if (s->reference) { /* a flat metal strip facing the antennas */
        double w = s->reference_width_m, y0 = s->reference_y_m - s->reference_height_m / 2;
        add_rect(b, X, -w / 2, w / 2, Y, y0, y0 + s->reference_height_m, Z, s->reference_z_m, -1, m2, -1.0,
                 1);
    }
    if (s->barrier) {
        double n_oil = sqrt(s->eps_r), n_b = sqrt(s->barrier_eps_r);
        double r1 = (n_oil - n_b) / (n_oil + n_b);
        double back = -r1 * (1.0 - r1 * r1); /* back face, through the front face twice */
        double y0 = s->barrier_y_min_m, y1 = s->barrier_y_max_m;
        int ny = cells(y1 - y0, size);
        double dy = (y1 - y0) / ny;
        if (m2) {
            double n[3] = {0, 0, -1};
            for (int j = 0; j < ny; j++) {
                double p[3] = {0, y0 + (j + 0.5) * dy, g->barrier_front_z};
                struct sim_element *e = add_world(b, p, n, dy, r1, 0);
                if (e) {
                    e->refl2 = back;
                    e->behind_barrier = 0;
                }
            }
        } else {
            double R = g->barrier_outer_r;
            int np = cells(M_PI * R, size);
            double dp = M_PI / np;
            for (int i = 0; i < np; i++) {
                double phi = -M_PI / 2 + (i + 0.5) * dp;
                double n[3] = {sin(phi), 0, -cos(phi)};
                for (int j = 0; j < ny; j++) {
                    double p[3] = {R * n[0], y0 + (j + 0.5) * dy, axis_z + R * n[2]};
                    struct sim_element *e = add_world(b, p, n, R * dp * dy, r1, 0);
                    if (e) {
                        e->refl2 = back;
                        e->behind_barrier = 0;
                    }
                }
            }
        }
    }
}

int sim_geometry_build(const struct sim_scene *s, struct sim_geometry *g, char *err, size_t errlen)
{
    memset(g, 0, sizeof *g);
    g->mode = s->mode;
    g->element_size_m = sim_geometry_element_size(s);
    sim_stack_frame(s, g->rot, g->origin);
    g->half_height = 0.5 * sim_scene_stack_height_m(s);
    g->radius = s->outer_radius_m;
    g->build = s->radial_build_m;
    g->face_local_z = -s->outer_radius_m;
    g->has_barrier = s->clutter && s->barrier;
    g->barrier_axis_z = s->face_z_m + s->outer_radius_m;
    g->barrier_outer_r = s->outer_radius_m + s->barrier_gap_m + s->barrier_thickness_m;
    g->barrier_front_z = s->face_z_m - s->barrier_gap_m - s->barrier_thickness_m;
    g->barrier_y_min = s->barrier_y_min_m;
    g->barrier_y_max = s->barrier_y_max_m;
    g->barrier_thickness = s->barrier_thickness_m;
    g->barrier_n = sqrt(s->barrier_eps_r);

    g->front = calloc((size_t)s->disks, sizeof *g->front);
    struct front_seg *seg = malloc((2 * (size_t)s->disks) * sizeof *seg);
    if (!g->front || !seg) {
        free(seg);
        sim_geometry_free(g);
        snprintf(err, errlen, "geometry: out of memory for %d disks", s->disks);
        return -1;
    }
    if (sim_scene_disk_fronts(s, g->front, err, errlen) != 0) {
        free(seg);
        sim_geometry_free(g);
        return -1;
    }
    double least = g->front[0];
    for (int i = 1; i < s->disks; i++)
        least = fmin(least, g->front[i]);
    g->solid_radius = g->radius + least;
    g->solid_front_z = g->face_local_z - least;
    size_t nseg = front_profile(s, g, seg);

    struct builder b = {g, s, 0, 0};
    if (s->mode == SIM_MODE_2D)
        build_winding_2d(s, &b, seg, nseg);
    else
        build_winding_3d(s, &b, seg, nseg);
    free(seg);
    if (s->clutter) {
        struct sim_scene cl = *s;
        cl.barrier = g->has_barrier;
        build_clutter(&cl, &b);
    }
    if (!b.failed && s->edge_diffraction && build_edges(s, g) != 0)
        b.failed = 1;
    if (b.failed) {
        sim_geometry_free(g);
        snprintf(err, errlen, "geometry: out of memory for surface elements");
        return -1;
    }
    return 0;
}

void sim_geometry_free(struct sim_geometry *g)
{
    free(g->el);
    free(g->edges);
    free(g->front);
    g->el = NULL;
    g->edges = NULL;
    g->front = NULL;
    g->count = g->edge_count = 0;
}

int sim_geometry_blocked(const struct sim_geometry *g, const double a[3], const double p[3])
{
    double h = g->half_height;
    if (g->mode == SIM_MODE_2D) {
        /* clip the segment a->p to the rectangle z in [zf, zf+build], y in [-h, h] */
        double s0 = 0.0, s1 = 1.0;
        double lo[2] = {g->solid_front_z, -h}, hi[2] = {g->face_local_z + g->build, h};
        int axis[2] = {2, 1};
        for (int k = 0; k < 2; k++) {
            int ax = axis[k];
            double d = p[ax] - a[ax];
            if (fabs(d) < 1e-15) {
                if (a[ax] < lo[k] || a[ax] > hi[k])
                    return 0;
                continue;
            }
            double t0 = (lo[k] - a[ax]) / d, t1 = (hi[k] - a[ax]) / d;
            if (t0 > t1) {
                double t = t0;
                t0 = t1;
                t1 = t;
            }
            if (t0 > s0)
                s0 = t0;
            if (t1 < s1)
                s1 = t1;
            if (s0 >= s1)
                return 0;
        }
        return 1;
    }
    double ax = a[0], az = a[2], dx = p[0] - a[0], dz = p[2] - a[2];
    double dd = dx * dx + dz * dz;
    double R = g->solid_radius;
    if (dd < 1e-24)
        return 0;
    double ad = ax * dx + az * dz;
    double disc = ad * ad - dd * (ax * ax + az * az - R * R);
    if (disc <= 0)
        return 0;
    double sq = sqrt(disc);
    double s0 = (-ad - sq) / dd, s1 = (-ad + sq) / dd;
    if (s0 < 0)
        s0 = 0;
    if (s1 > 1)
        s1 = 1;
    if (s0 >= s1)
        return 0;
    double y0 = a[1] + s0 * (p[1] - a[1]), y1 = a[1] + s1 * (p[1] - a[1]);
    double ylo = fmin(y0, y1), yhi = fmax(y0, y1);
    return yhi > -h && ylo < h;
}

/* The part of segment a->p (parameter s in [0, 1]) inside the stack's
 * footprint: a disc of the outer radius (3-D) or the rectangle's depth (2-D).
 * Returns 0 if the segment misses it. */
static int footprint_span(const struct sim_geometry *g, const double a[3], const double p[3], double *s0,
                          double *s1)
{
    if (g->mode == SIM_MODE_2D) {
        double dz = p[2] - a[2];
        double lo = g->solid_front_z, hi = g->face_local_z + g->build;
        if (fabs(dz) < 1e-15)
            return 0;
        double t0 = (lo - a[2]) / dz, t1 = (hi - a[2]) / dz;
        if (t0 > t1) {
            double t = t0;
            t0 = t1;
            t1 = t;
        }
        *s0 = fmax(t0, 0.0);
        *s1 = fmin(t1, 1.0);
        return *s0 < *s1;
    }
    double ax = a[0], az = a[2], dx = p[0] - a[0], dz = p[2] - a[2];
    double dd = dx * dx + dz * dz, R = g->solid_radius;
    if (dd < 1e-24)
        return 0;
    double ad = ax * dx + az * dz;
    double disc = ad * ad - dd * (ax * ax + az * az - R * R);
    if (disc <= 0)
        return 0;
    double sq = sqrt(disc);
    *s0 = fmax((-ad - sq) / dd, 0.0);
    *s1 = fmin((-ad + sq) / dd, 1.0);
    return *s0 < *s1;
}

double sim_geometry_shadow_weight(const struct sim_geometry *g, const double a[3], const double p[3],
                                  double lambda)
{
    double h = g->half_height, s0, s1;
    if (!footprint_span(g, a, p, &s0, &s1))
        return 1.0;
    if (s1 >= 1.0 && fabs(p[1]) <= h)
        return 0.0; /* inside the stack's own volume, e.g. the core within the winding */
    double y0 = a[1] + s0 * (p[1] - a[1]), y1 = a[1] + s1 * (p[1] - a[1]);
    double ylo = fmin(y0, y1), yhi = fmax(y0, y1);
    double clearance;
    if (ylo >= h)
        clearance = ylo - h;
    else if (yhi <= -h)
        clearance = -h - yhi;
    else
        clearance = -fmin(yhi + h, h - ylo); /* cuts into the stack: negative */
    double len =
        sqrt((p[0] - a[0]) * (p[0] - a[0]) + (p[1] - a[1]) * (p[1] - a[1]) + (p[2] - a[2]) * (p[2] - a[2]));
    double d1 = fmax(s0 * len, 1e-6), d2 = fmax((1.0 - s0) * len, 1e-6);
    double v = -clearance * sqrt(2.0 * (d1 + d2) / (lambda * d1 * d2));
    if (v <= -0.78)
        return 1.0;
    double loss_db = 6.9 + 20.0 * log10(sqrt((v - 0.1) * (v - 0.1) + 1.0) + v - 0.1);
    return pow(10.0, -loss_db / 20.0);
}
