/* The scene cut into small surface elements for the physical-optics
 * integral, plus the stack's frame (displacement, tilt) and the simple
 * solids used for shadowing. Coordinates: x horizontal along the tank wall,
 * y up, z range from the antenna line; the antennas move along x = z = 0.
 *
 * The winding is generated in its own frame ("local": origin at the stack's
 * centre on its axis, y along the axis) and rotated/translated into the
 * world; the clutter is static in the world. */
#ifndef UWBSIM_SURFACES_H
#define UWBSIM_SURFACES_H

#include <stddef.h>

#include "scene.h"

/* Which contributions a trace holds (bit mask). */
enum sim_part {
    SIM_PART_WINDING = 1,
    SIM_PART_CLUTTER = 2, /* core, barrier, clamp, far wall */
    SIM_PART_DIRECT = 4,  /* Tx-Rx coupling and the window's own echoes */
    SIM_PART_ALL = 7
};

enum sim_element_kind {
    SIM_ELEM_PLAIN,   /* lit where it faces both antennas */
    SIM_ELEM_GAP_UP,  /* top face of a disk, seen only through the gap above it */
    SIM_ELEM_GAP_DOWN /* bottom face of a disk, seen only through the gap below it */
};

struct sim_element {
    double pos[3];                /* world */
    double nrm[3];                /* world, unit, outward */
    double lpos[3];               /* in the stack frame (gap and shadow tests) */
    double area;                  /* m^2 in 3-D, m in 2-D */
    double refl;                  /* reflection coefficient of the surface */
    double refl2;                 /* thin layer: back face's coefficient (transmissions included), else 0 */
    double depth0, depth1;        /* gap faces: element's span of depth behind the outer rim */
    double gap;                   /* gap faces: axial gap width */
    double mouth;                 /* gap faces (3-D): radius of the gap's mouth, the nearer disk's rim */
    unsigned char kind;           /* enum sim_element_kind */
    unsigned char part;           /* SIM_PART_WINDING or SIM_PART_CLUTTER */
    unsigned char shadowable;     /* may be hidden behind the winding */
    unsigned char behind_barrier; /* rays to it cross the pressboard barrier */
};

/* A straight piece of a wedge edge (a point in 2-D) for the PTD fringe term.
 * Face A and face B meet at the edge; s_* points from the edge into a face,
 * n_* is that face's outward normal. Angles in the plane normal to the edge
 * are measured from face A (0) through the outside to face B (wedge_n pi). */
struct sim_edge {
    double pos[3], lpos[3];
    double tangent[3];
    double s_a[3], n_a[3];
    double wedge_n;
    double length; /* m in 3-D; 1 in 2-D */
};

struct sim_geometry {
    int mode; /* enum sim_mode */
    double element_size_m;
    /* stack frame: world = origin + rot * local */
    double rot[3][3];
    double origin[3];
    double half_height;  /* local y of the stack spans [-h, h] */
    double radius;       /* outer radius (3-D) */
    double build;        /* radial build / 2-D depth */
    double face_local_z; /* local z of the front face (= -radius) */
    /* Radial changes: each disk's front offset (m, + toward the antennas,
     * i.e. outward: local z -radius - front, radius + front in 3-D), bottom
     * disk first; the solid that shadows reaches to the least moved front. */
    double *front;
    double solid_radius;  /* 3-D: radius + the smallest front */
    double solid_front_z; /* 2-D: face_local_z - the smallest front */
    /* barrier (static, world): outer face radius about the undisplaced axis */
    int has_barrier;
    double barrier_axis_z;  /* world z of the undisplaced winding axis */
    double barrier_outer_r; /* 3-D radius of the outer face */
    double barrier_front_z; /* 2-D: z of the outer (front) face */
    double barrier_y_min, barrier_y_max;
    double barrier_thickness, barrier_n;
    struct sim_element *el;
    size_t count;
    struct sim_edge *edges;
    size_t edge_count;
};

/* Medium's shortest wavelength of interest over 8 (3-D) or 16 (2-D) unless set. */
double sim_geometry_element_size(const struct sim_scene *scene);
int sim_geometry_build(const struct sim_scene *scene, struct sim_geometry *geo, char *err, size_t errlen);
void sim_geometry_free(struct sim_geometry *geo);

/* The stack's frame from displacement and tilt: world = origin + rot * local. */
void sim_stack_frame(const struct sim_scene *scene, double rot[3][3], double origin[3]);
/* World point -> stack frame. */
void sim_geometry_to_local(const struct sim_geometry *geo, const double world[3], double local[3]);
/* Is the straight segment from antenna a (stack frame) to element point p
 * (stack frame) blocked by the winding, taken as a solid cylinder (3-D) or
 * a solid rectangle (2-D)? */
int sim_geometry_blocked(const struct sim_geometry *geo, const double a[3], const double p[3]);
/* How much of the field from antenna a reaches p past the winding: 1 in the
 * clear, 0 for points enclosed by the stack, and in between a knife-edge
 * diffraction taper (ITU-R P.526 single-edge loss at wavelength lambda) set
 * by how far the straight ray clears, or cuts into, the stack. */
double sim_geometry_shadow_weight(const struct sim_geometry *geo, const double a[3], const double p[3],
                                  double lambda);

#endif
