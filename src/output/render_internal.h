/* The PNG code's building blocks: canvas, font, colour maps, plot frames,
 * axes, captions and the layouts of the three images. Shared by the
 * src/output/png_*.c files and their tests; not part of the library's API
 * (uwb/render.h is). */
#ifndef UWB_OUTPUT_RENDER_INTERNAL_H
#define UWB_OUTPUT_RENDER_INTERNAL_H

#include <stddef.h>

#include "uwb/render.h"

/* ------------------------------------------------------------------ */
/* Building blocks (shared by the png_*.c files; exposed for tests)    */
/* ------------------------------------------------------------------ */

struct uwb_rgb {
    unsigned char r, g, b;
};

/* An 8-bit RGB raster, row-major, origin top-left. */
struct uwb_canvas {
    int width, height;
    unsigned char *rgb; /* width * height * 3 */
};

int uwb_canvas_init(struct uwb_canvas *c, int width, int height, struct uwb_rgb background, char *err,
                    size_t errlen);
void uwb_canvas_free(struct uwb_canvas *c);
/* Drawing clips silently to the canvas. */
void uwb_canvas_put(struct uwb_canvas *c, int x, int y, struct uwb_rgb colour);
struct uwb_rgb uwb_canvas_get(const struct uwb_canvas *c, int x, int y);
void uwb_canvas_fill_rect(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb colour);
void uwb_canvas_frame_rect(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb colour);
/* A line `thickness` px wide (square brush). dash_on/dash_off in px; 0
 * dash_off draws it solid. */
void uwb_canvas_line(struct uwb_canvas *c, int x0, int y0, int x1, int y1, struct uwb_rgb colour,
                     int thickness, int dash_on, int dash_off);
/* Connected segments; the dash pattern runs on across the joints. */
void uwb_canvas_polyline(struct uwb_canvas *c, const int *xs, const int *ys, int n, struct uwb_rgb colour,
                         int thickness, int dash_on, int dash_off);

/* Key/value pairs stored as PNG text chunks (e.g. "Title", "Description"):
 * ASCII text as tEXt, anything else as UTF-8 in iTXt (tEXt is Latin-1). A
 * NULL text is left out. */
struct uwb_png_text {
    const char *key;
    const char *text;
};

/* Write the canvas as an 8-bit RGB PNG, atomically. Returns 0, or -1 with
 * "PATH: problem"; on failure nothing new is left at PATH. */
int uwb_canvas_write_png(const struct uwb_canvas *c, const char *path, const struct uwb_png_text *texts,
                         int n_texts, char *err, size_t errlen);

/* Bitmap font: printable ASCII plus a few signs (UTF-8 "±", "°", "Δ", "σ").
 * Glyph box is 5x7 above the baseline with 2 rows of descender, on a 6 px
 * advance and an 11 px line, times `scale`. Returns the advance width. */
#define UWB_FONT_ADVANCE 6
#define UWB_FONT_CAP_HEIGHT 7
#define UWB_FONT_LINE_HEIGHT 11
int uwb_text_width(const char *utf8, int scale);
/* Bytes of `text` that make its next line no wider than max_w pixels:
 * up to the last space that fits, mid-word when one word is wider than
 * the line, and at least one glyph, so a wrapping loop always advances.
 * The caller skips the spaces between lines (src/output/png_caption.c). */
size_t uwb_wrap_line_length(const char *utf8, int max_w, int scale);
/* (x, y) is the top-left of the text box (y = top of capitals). */
int uwb_draw_text(struct uwb_canvas *c, int x, int y, const char *utf8, int scale, struct uwb_rgb colour);
/* Text rotated 90 degrees counter-clockwise (reads bottom to top); (x, y)
 * is where the text starts: its baseline-left corner after rotation,
 * i.e. the text runs upward from y and occupies x .. x + cap height. */
int uwb_draw_text_up(struct uwb_canvas *c, int x, int y, const char *utf8, int scale, struct uwb_rgb colour);
/* 1 if the font has a glyph for this code point. */
int uwb_font_has_glyph(unsigned codepoint);
/* 1 if the glyph table is in the order its index lookup assumes and every
 * row is 5 columns (a self-check for tests). */
int uwb_font_table_consistent(void);

/* Colour maps. t is clamped to [0, 1]. */
struct uwb_rgb uwb_colormap_perceptual(double t); /* dark violet -> yellow, lightness rises monotonically */
struct uwb_rgb uwb_colormap_diverging(double t);  /* 0 blue, 0.5 white, 1 red */

/* CIE L* (0..100) of an sRGB colour: how light it looks. */
double uwb_rgb_lightness(struct uwb_rgb c);

/* Colours with a meaning in every image (the legend names them). */
extern const struct uwb_rgb UWB_RGB_CURRENT_EDGE;  /* solid line */
extern const struct uwb_rgb UWB_RGB_BASELINE_EDGE; /* dashed line */
extern const struct uwb_rgb UWB_RGB_HALO;          /* outline that keeps lines visible on any colour */
extern const struct uwb_rgb UWB_RGB_SEARCH_WINDOW; /* the analysis's search window on the B-scan */
extern const struct uwb_rgb UWB_RGB_NOT_MEASURED;  /* grey of a displacement not measured (comparison) */

/* ------------------------------------------------------------------ */
/* Plot geometry                                                       */
/* ------------------------------------------------------------------ */

/* A data rectangle mapped onto pixels. x grows right, y grows UP (data y
 * max is the top pixel row). Pixel column plot.x maps to x_min and column
 * plot.x + plot.w - 1 to x_max; row plot.y maps to y_max and row
 * plot.y + plot.h - 1 to y_min. */
struct uwb_plot {
    int x, y, w, h;
    double x_min, x_max;
    double y_min, y_max;
};

double uwb_plot_px_x(const struct uwb_plot *p, double x); /* fractional pixel column */
double uwb_plot_px_y(const struct uwb_plot *p, double y); /* fractional pixel row */
int uwb_plot_col(const struct uwb_plot *p, double x);     /* rounded */
int uwb_plot_row(const struct uwb_plot *p, double y);     /* rounded */

/* "Nice" tick values (1, 2 or 5 x 10^n apart) inside [lo, hi], about
 * `target` of them. Returns the count; *step gets the spacing. */
int uwb_nice_ticks(double lo, double hi, int target, double *ticks, int max_ticks, double *step);
/* Tick label with as many decimals as the step needs, never "-0". */
void uwb_format_tick(char *buf, size_t len, double value, double step);

struct uwb_axis_style {
    double x_label_scale; /* labels show data * scale (1000: metres -> mm, 1e9: s -> ns) */
    double y_label_scale;
    int font_scale;       /* 1 or more */
    int x_ticks, y_ticks; /* about how many ticks (0: default) */
    int x_labels;         /* label the x ticks */
    int y_labels_left, y_labels_right;
    const char *x_title, *y_title, *y_title_right; /* NULL: none */
    int panel_gap; /* > 0: x labels may not reach past half this gap (panels side by side) */
};

/* Frame the plot, tick both axes outward and label the ticks. */
void uwb_draw_axes(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_axis_style *s);

/* Vertical colour bar at (x, y, w, h): top row map(1), bottom row map(0);
 * ticks at positions tick_t (0..1, 1 = top) labelled to the right; title
 * above. */
void uwb_draw_colorbar(struct uwb_canvas *c, int x, int y, int w, int h, struct uwb_rgb (*map)(double),
                       const double *tick_t, const char *const *labels, int n_ticks, const char *title,
                       int font_scale);

/* ------------------------------------------------------------------ */
/* Caption, intensity painting, edge overlays                          */
/* ------------------------------------------------------------------ */

/* Height of the caption block for this verdict on a canvas this wide
 * (long reasons wrap onto more lines). */
int uwb_caption_height(const struct uwb_verdict *v, const struct uwb_provenance *prov, int width,
                       int font_scale);
/* Title, scan id (else prov->scan_name) and time, verdict badge +
 * displacement, edges (this scan and baseline), then the source line
 * (uwb_describe_provenance). v and prov may be NULL. Returns the y where
 * the block ends. */
int uwb_draw_caption(struct uwb_canvas *c, const char *title, const struct uwb_verdict *v,
                     const struct uwb_provenance *prov, int font_scale);
/* "asset phase B   stack 64 pulses/position   eps_r 3.20   SNR 24.1 dB   uwbd 0.1.0" */
void uwb_describe_provenance(const struct uwb_verdict *v, const struct uwb_provenance *prov, char *buf,
                             size_t len);
/* 1 if the verdict carries a displacement (ok/watch/alarm with both scans'
 * edges): only then may an image draw one. */
int uwb_displacement_measured(const struct uwb_verdict *v);
struct uwb_rgb uwb_status_colour(enum uwb_status status);
/* "displacement +2.40 ± 0.31 mm (up) ..." or why there is none. */
void uwb_describe_displacement(const struct uwb_verdict *v, char *buf, size_t len);
/* "lower 247.0 ± 0.5 upper ... mm" or "not found: reason". */
void uwb_describe_edges(const struct uwb_edges *e, char *buf, size_t len);
/* The caption in one line (stored as the PNG's Description text). */
void uwb_verdict_summary(const struct uwb_verdict *v, const struct uwb_provenance *prov, char *buf,
                         size_t len);
/* Write the canvas as `path` with Title (title), Description (the verdict
 * summary), Software ("uwbd VERSION") and, where known, Scan, Asset, Stack,
 * eps_r, "SNR dB" and (against a baseline) Radial text chunks, then free it. */
int uwb_canvas_save_with_verdict(struct uwb_canvas *c, const char *path, const char *title,
                                 const struct uwb_verdict *v, const struct uwb_provenance *prov, char *err,
                                 size_t errlen);

/* -1 with "NAME: problem" if the image cannot be drawn (no data, < 2x2,
 * non-positive spacing). */
int uwb_image_check(const struct uwb_image *img, const char *name, char *err, size_t errlen);
double uwb_image_peak(const struct uwb_image *img);   /* largest finite value >= 0 */
double uwb_image_peak_z(const struct uwb_image *img); /* range of the brightest pixel */
/* Colour-map position (0..1) of an amplitude in dB re peak, floor_db -> 0. */
double uwb_db_to_t(double amplitude, double peak, double floor_db);
/* Fill the plot rectangle with the image in dB re peak (plot x = z, y = y). */
void uwb_paint_image_db(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                        double peak, double floor_db);

enum uwb_edge_kind { UWB_EDGE_CURRENT, UWB_EDGE_BASELINE };
/* A horizontal edge line in its style (core on `row`, halo around). */
void uwb_draw_edge_hline(struct uwb_canvas *c, int x0, int x1, int row, enum uwb_edge_kind kind);
void uwb_draw_centre_marker(struct uwb_canvas *c, int cx, int cy, enum uwb_edge_kind kind);
/* Lower and upper edge lines from x_from to x_to (plot x units), a centre
 * marker at x_marker (NAN: none), the heights in mm written at the right (label_side
 * 1) or left (-1) end, or not (0). Nothing if !e->found. */
void uwb_draw_edges(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_edges *e,
                    enum uwb_edge_kind kind, double x_from, double x_to, double x_marker, int label_side,
                    int font_scale);
/* One legend line at (x, y); returns its width. */
int uwb_draw_edge_legend(struct uwb_canvas *c, int x, int y, int with_current, int with_baseline,
                         int font_scale);

/* Caption on top, plot, colour bar right, legend below (pixel geometry
 * only: the caller sets the plot's data ranges). */
void uwb_layout_single_plot(int width, int height, int font_scale, int caption_height, struct uwb_plot *plot,
                            int *colorbar_x, int *colorbar_w);
int uwb_layout_legend_y(const struct uwb_plot *plot, int font_scale);

/* The intensity colour bar: 0 dB (peak) at the top, floor_db at the bottom. */
void uwb_draw_db_colorbar(struct uwb_canvas *c, int x, int y, int w, int h, double floor_db, int font_scale);

/* ------------------------------------------------------------------ */
/* Watch and alarm thresholds (png_thresholds.c)                       */
/* ------------------------------------------------------------------ */

/* 1 if th is set and sane (0 < watch <= alarm). */
int uwb_thresholds_usable(const struct uwb_thresholds *th);
/* ok, watch or alarm for a displacement, by the thresholds alone. */
enum uwb_status uwb_threshold_zone(double displacement_m, const struct uwb_thresholds *th);
struct uwb_rgb uwb_rgb_blend(struct uwb_rgb under, struct uwb_rgb over, double alpha);
/* Tint the plot's rows whose distance from `centre` (plot y units;
 * data_per_m of them to a metre) is in the watch or the alarm zone with
 * that status's colour at `alpha`; the ok zone is left alone. */
void uwb_tint_threshold_zones(struct uwb_canvas *c, const struct uwb_plot *p, double centre,
                              const struct uwb_thresholds *th, double data_per_m, double alpha);
/* The displacement meter in the captions' limits line: a bar at (x, y,
 * w, h) spanning -half_range_m .. +half_range_m of displacement (1.6 x
 * the alarm threshold, or more to hold this displacement and its 95 %
 * interval), each column in its zone's colour, zero marked; a measured
 * displacement drawn as a mark with its 95 % interval (UWB_SIGMAS_95
 * sigma) as a capped bar (measured: uwb_displacement_measured(v)). */
struct uwb_meter {
    int x, y, w, h;
    double half_range_m;
};
/* What a meter shows: the axial displacement, or the radial change on a
 * verdict the radial change decided (measured 0: zones only). */
struct uwb_meter_figure {
    int measured;
    double value_m, sigma_m; /* sigma: 1-sigma */
};
void uwb_meter_layout(const struct uwb_meter_figure *f, const struct uwb_thresholds *th, int x, int y, int w,
                      int h, struct uwb_meter *m);
int uwb_meter_col(const struct uwb_meter *m, double displacement_m);
void uwb_draw_meter(struct uwb_canvas *c, const struct uwb_meter *m, const struct uwb_meter_figure *f,
                    const struct uwb_thresholds *th);
/* The meter's numbers, in a row under it: the figure (when measured), the
 * alarm and watch limits either side in mm with their signs ("-5", "+5"),
 * zero; a label within two glyphs of one drawn before is left out.
 * uwb_meter_labels_height: the row's height. */
void uwb_draw_meter_labels(struct uwb_canvas *c, const struct uwb_meter *m, const struct uwb_meter_figure *f,
                           const struct uwb_thresholds *th, int scale);
int uwb_meter_labels_height(int scale);
/* 1 and the meter's place if this caption has one (thresholds given). */
int uwb_caption_meter(const struct uwb_verdict *v, const struct uwb_provenance *prov, int width,
                      int font_scale, struct uwb_meter *m);

/* B-scan: colour-map position of a signed amplitude on the signed dB
 * scale (0.5 = zero or below floor_db, 1 = +peak, 0 = -peak). */
double uwb_signed_db_to_t(double value, double peak, double floor_db);
/* Two-way time of the specular echo of a plane face at range face_z_m
 * for this scan's antenna pair and medium. */
double uwb_face_echo_time(const struct uwb_scan *scan, double face_z_m);
/* Ring and label "not the winding" up to two returns on the migrated image
 * within 6 dB of the face's peak (or brighter) but away from the face the
 * edges e describe (src/output/png_strong_returns.c). */
void uwb_mark_strong_returns(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                             const struct uwb_edges *e, int label_scale);
/* A reflector across the image's height away from the face the edges e
 * describe: a range column within 20 dB of the face's peak over 60 % of
 * the rows or more (src/output/png_reflector_band.c). 1 and its range
 * in *z_m if there is one (the brightest such column). */
int uwb_find_reflector_band(const struct uwb_image *img, const struct uwb_edges *e, double *z_m);
/* Label it on the migrated image: "reflector at 520 mm / full height: /
 * not the winding", with a tick to the band. */
void uwb_mark_reflector_band(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *img,
                             const struct uwb_edges *e, int label_scale);
/* Hatch the plot's rows outside prov's antenna travel, dash its ends and
 * (label_scale > 0) say "beyond antenna travel" where there is room. */
void uwb_mark_antenna_travel(struct uwb_canvas *c, const struct uwb_plot *p,
                             const struct uwb_provenance *prov, int label_scale);
/* Its inverse: the range of a face whose echo arrives at t_s; NAN before
 * the earliest possible echo. */
double uwb_face_range_at_time(const struct uwb_scan *scan, double t_s);

/* Where uwb_render_migrated_png puts its plot for this image and options (data
 * units: metres). For tests and for anyone annotating the PNG afterwards. */
void uwb_render_migrated_layout(const struct uwb_image *intensity, const struct uwb_verdict *v,
                                const struct uwb_render_options *opt, struct uwb_plot *plot, int *colorbar_x,
                                int *colorbar_w);
/* Likewise for the B-scan (x: time in s, y: antenna height in m). */
void uwb_render_bscan_layout(const struct uwb_scan *scan, const struct uwb_verdict *v,
                             const struct uwb_render_options *opt, struct uwb_plot *plot, int *colorbar_x,
                             int *colorbar_w);
/* Likewise for the comparison's four panels (the difference panel like
 * the image panels; profile x: brightness / peak, 0..1.05). */
void uwb_render_comparison_layout(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                                  const struct uwb_verdict *v, const struct uwb_render_options *opt,
                                  struct uwb_plot *base_panel, struct uwb_plot *current_panel,
                                  struct uwb_plot *difference_panel, struct uwb_plot *profile_panel,
                                  int *colorbar_x, int *colorbar_w);
/* The comparison's difference panel: current/its peak - baseline/its
 * peak, diverging map, full colour at the largest |difference| (returned). */
double uwb_paint_difference(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_image *current,
                            const struct uwb_image *baseline);
/* The comparison's radial panel (src/output/png_radial.c): the face's
 * range along the height in both scans, aligned by the compare shift,
 * x in m toward the antenna re the baseline's median range. */
void uwb_render_comparison_radial_layout(const struct uwb_analysis *current,
                                         const struct uwb_analysis *baseline, const struct uwb_verdict *v,
                                         const struct uwb_render_options *opt, struct uwb_plot *radial_panel);
/* The radial panel's two curves as drawn, (this scan's y, m toward the
 * antenna) points: the baseline's rows between its edges moved up by the
 * shift, this scan's rows over the same heights. x is re the baseline's
 * median range; this scan's curve less the verdict's radial line (the
 * whole face's move and its tilt; none where not measured), so the curves
 * stand apart by the verdict's change. 0, or -1 (nothing to draw; k
 * empty). */
struct uwb_radial_curves {
    int n_base, n_cur;
    double *yb, *xb, *yc, *xc;
};
int uwb_radial_curves_read(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                           const struct uwb_verdict *v, struct uwb_radial_curves *k);
void uwb_radial_curves_free(struct uwb_radial_curves *k);
/* Sets p's x range (m) to hold both curves, at least +/- 3 mm. */
void uwb_radial_panel_range(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                            const struct uwb_verdict *v, struct uwb_plot *p);
void uwb_draw_radial_panel(struct uwb_canvas *c, const struct uwb_plot *p, const struct uwb_analysis *current,
                           const struct uwb_analysis *baseline, const struct uwb_verdict *v, int font_scale);
/* The radial panel's line on what was taken out: "face as a whole +0.4 mm,
 * tilt -1.2 mm, taken out", or with the tilt withheld "... taken out; tilt
 * withheld"; empty when the change was not measured. */
void uwb_radial_level_text(const struct uwb_verdict *v, char *buf, size_t len);
/* The colour of the rows past the watch limit in the radial panel. */
struct uwb_rgb uwb_radial_shade_colour(enum uwb_status status);
/* value with its sign and `decimals` decimals, "0.0" (never "-0.0")
 * where it rounds to zero. */
void uwb_format_signed(char *buf, size_t len, double value, int decimals);
/* "radial +3.1 ± 0.4 mm at 267 mm (bulge toward the antenna)", a change
 * whose 95 % interval holds zero "(within its noise)", or
 * "radial: not measured (why)", or "radial: no baseline". */
void uwb_describe_radial(const struct uwb_verdict *v, char *buf, size_t len);
/* The points of a face profile's curve in the comparison's profile panel:
 * one per profile sample inside the panel's heights, x = value / the
 * profile's peak. xs and ys hold profile->n entries; returns how many were
 * filled (0 for an empty or all-zero profile). */
int uwb_comparison_profile_polyline(const struct uwb_plot *profile_panel,
                                    const struct uwb_face_profile *profile, int *xs, int *ys);

#endif
