/* The PNG images an engineer archives and reads: the migrated image, the raw
 * B-scan and the baseline/current comparison, each with a caption that names
 * the scan, its time and the verdict so the PNG can be read on its own.
 *
 * Written by uwbd itself with libpng and a bitmap font of our own (no font
 * package on the board, byte-identical output for identical input). Every
 * file is written atomically (atomic_file.h): a failure leaves the old file,
 * or nothing, behind. */
#ifndef UWB_RENDER_H
#define UWB_RENDER_H

#include <stddef.h>

#include "uwb/analysis.h"
#include "uwb/image.h"
#include "uwb/scan.h"
#include "uwb/verdict.h"

/* Where an image came from, for its caption and its text chunks, so the
 * PNG alone tells an engineer what was measured on what. Each field may be
 * unset (NULL, "" or 0). The software version is always added. */
struct uwb_provenance {
    const char *scan_name; /* names the scan when the verdict has no scan id (a replayed file's stem) */
    const char *asset;     /* the asset as the site names it (site.phase, site.label) */
    int stack;             /* pulses averaged per antenna position */
    double eps_r;          /* relative permittivity the image was focused with */
    /* What the verdict was judged by: the watch and alarm thresholds, drawn
     * as zones around the baseline centre and named in the caption (NULL:
     * not drawn). */
    const struct uwb_thresholds *thresholds;
    /* The radial change's limits: on a verdict the radial change decided
     * (the axial figure withheld, or a radial watch or alarm) the caption
     * shows them too (NULL: not shown). */
    const struct uwb_thresholds *radial_thresholds;
    int became_baseline; /* this scan was made the baseline (a commissioning scan): the captions say so */
    /* The antenna's travel (lowest and highest position), hatched beyond on
     * the images whose height axis reaches past it (has_travel 0: not drawn). */
    int has_travel;
    double travel_lo_m, travel_hi_m;
    /* The ranges the analysis searched for the face, marked on the B-scan
     * at their echo times (has_search_window 0: not drawn). */
    int has_search_window;
    double search_z_lo_m, search_z_hi_m;
};

/* ------------------------------------------------------------------ */
/* The three images                                                   */
/* ------------------------------------------------------------------ */

struct uwb_render_options {
    int width, height;     /* canvas size in pixels */
    double floor_db;       /* migrated / comparison colour floor re image peak (< 0, default -30) */
    double bscan_floor_db; /* raw B-scan: |amplitude| below this re the peak shows as zero (default -40) */
    int font_scale;        /* text size: 1 = 5x7 px capitals, 2 (default) = 10x14 */
    const struct uwb_provenance *provenance; /* where the scan came from (NULL: the verdict alone) */
    int bscan_conditioned; /* the B-scan's traces are the conditioned ones the migration ran on (titles say
                              so) */
};

void uwb_render_options_default(struct uwb_render_options *opt);
/* Copy `in` (may be NULL) replacing out-of-range fields by defaults. */
void uwb_render_options_sane(const struct uwb_render_options *in, struct uwb_render_options *out);

/* Migrated intensity image (linear envelope >= 0) in dB re its peak, y up,
 * z across, edges of v->current solid, v->baseline dashed. v may be NULL
 * (no overlay, caption says so). Returns 0, or -1 with "PATH: problem". */
int uwb_render_migrated_png(const char *path, const struct uwb_image *intensity, const struct uwb_verdict *v,
                            char *err, size_t errlen);
int uwb_render_migrated_png_opt(const char *path, const struct uwb_image *intensity,
                                const struct uwb_verdict *v, const struct uwb_render_options *opt, char *err,
                                size_t errlen);

/* Traces: antenna y (mm) vertical, time (ns) across, signed amplitude in
 * a diverging map on a signed dB scale. The title says "raw", or
 * "conditioned" with opt->bscan_conditioned (uwb_write_images draws the
 * analysis's conditioned traces, the ones that were migrated). */
int uwb_render_bscan_png(const char *path, const struct uwb_scan *scan, const struct uwb_verdict *v,
                         char *err, size_t errlen);
int uwb_render_bscan_png_opt(const char *path, const struct uwb_scan *scan, const struct uwb_verdict *v,
                             const struct uwb_render_options *opt, char *err, size_t errlen);

/* Baseline panel | current panel (both cropped to the face, same dB scale)
 * | this minus baseline (each re its peak, linear) | face profiles along y, edges and the centre shift
 * marked. It draws what each analysis measured: its display image and the face profile its edges were read
 * from (nothing is measured again here). baseline may be NULL: the baseline panel then says "no baseline" and
 * only the current image and profile are drawn, so the file set stays the same. */
int uwb_render_comparison_png(const char *path, const struct uwb_analysis *current,
                              const struct uwb_analysis *baseline, const struct uwb_verdict *v, char *err,
                              size_t errlen);
int uwb_render_comparison_png_opt(const char *path, const struct uwb_analysis *current,
                                  const struct uwb_analysis *baseline, const struct uwb_verdict *v,
                                  const struct uwb_render_options *opt, char *err, size_t errlen);

/* Write the migrated, B-scan and comparison PNGs into dir, named after
 * `stem`, and list them in v->images; without a migrated image (analysis
 * stopped before imaging) only the B-scan. The captions name the scan by
 * its id, else by `stem`. site (may be NULL) gives what the scan file does
 * not: the asset, the thresholds drawn; its scan name, stack
 * and eps_r are ignored (the scan's are used). */
int uwb_write_images(const char *dir, const char *stem, const struct uwb_provenance *site,
                     const struct uwb_scan *current, const struct uwb_analysis *current_analysis,
                     const struct uwb_analysis *baseline_analysis, struct uwb_verdict *v, char *err,
                     size_t errlen);

#endif
