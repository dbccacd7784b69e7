/* Where a replay spends its time, without touching the library: uwbbench is
 * linked with -Wl,--wrap=SYMBOL for a few library entry points (Makefile),
 * so the library's own calls to them land here, are timed, and go on to the
 * real function. */
#include "bench.h"

#include <string.h>

#include "uwb/condition.h"
#include "uwb/envelope.h"
#include "uwb/migrate.h"
#include "../../src/output/render_internal.h" /* the wrapped uwb_canvas_write_png */

static struct bench_stage_totals totals;

void bench_stages_reset(void)
{
    memset(&totals, 0, sizeof totals);
}

void bench_stages_read(struct bench_stage_totals *t)
{
    *t = totals;
}

const char *bench_stage_name(enum bench_stage s)
{
    static const char *const names[STAGE_COUNT] = {
        [STAGE_CONDITION] = "conditioning (uwb_condition_prepare, _finish)",
        [STAGE_DOMINANT] = "dominant frequency (uwb_dominant_frequency)",
        [STAGE_MIGRATE] = "migration (uwb_migrate, uwb_migration_plan_run)",
        [STAGE_ENVELOPE] = "envelope (uwb_envelope_along_z)",
        [STAGE_PNG_ENCODE] = "PNG encoding and file (uwb_canvas_write_png)",
    };
    return names[s];
}

static void count(enum bench_stage s, double since, int ny, int nz)
{
    double seconds = uwb_monotonic_s() - since;
    totals.seconds[s] += seconds;
    totals.calls[s]++;
    if (totals.n_calls < BENCH_MAX_CALLS)
        totals.call[totals.n_calls++] = (struct bench_stage_call){s, ny, nz, seconds};
}

/* The analysis' own steps, private to the library (headers in src/imaging):
 * declared here as the library defines them. */
struct uwb_migration_plan;

/* The real functions, as the linker names them under --wrap. */
int __real_uwb_condition_prepare(const struct uwb_scan *in, const struct uwb_geometry *g,
                                 const struct uwb_condition_options *opt, double dominant_hz,
                                 struct uwb_scan *out, char *err, size_t errlen);
int __real_uwb_condition_finish(const struct uwb_scan *prepared, const struct uwb_geometry *g,
                                const struct uwb_condition_options *opt, double dominant_hz,
                                const struct uwb_target_window *winding, struct uwb_scan *out, char *err,
                                size_t errlen);
int __real_uwb_dominant_frequency(const struct uwb_scan *scan, double *hz, char *err, size_t errlen);
int __real_uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan,
                       const struct uwb_geometry *geom, struct uwb_image *img, char *err, size_t errlen);
int __real_uwb_migration_plan_run(struct uwb_migration_plan *p, const struct uwb_scan *scan,
                                  const struct uwb_geometry *geom, struct uwb_image *img, char *err,
                                  size_t errlen);
int __real_uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen);
int __real_uwb_canvas_write_png(const struct uwb_canvas *c, const char *path,
                                const struct uwb_png_text *texts, int n_texts, char *err, size_t errlen);

int __wrap_uwb_condition_prepare(const struct uwb_scan *in, const struct uwb_geometry *g,
                                 const struct uwb_condition_options *opt, double dominant_hz,
                                 struct uwb_scan *out, char *err, size_t errlen);
int __wrap_uwb_condition_finish(const struct uwb_scan *prepared, const struct uwb_geometry *g,
                                const struct uwb_condition_options *opt, double dominant_hz,
                                const struct uwb_target_window *winding, struct uwb_scan *out, char *err,
                                size_t errlen);
int __wrap_uwb_dominant_frequency(const struct uwb_scan *scan, double *hz, char *err, size_t errlen);
int __wrap_uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan,
                       const struct uwb_geometry *geom, struct uwb_image *img, char *err, size_t errlen);
int __wrap_uwb_migration_plan_run(struct uwb_migration_plan *p, const struct uwb_scan *scan,
                                  const struct uwb_geometry *geom, struct uwb_image *img, char *err,
                                  size_t errlen);
int __wrap_uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen);
int __wrap_uwb_canvas_write_png(const struct uwb_canvas *c, const char *path,
                                const struct uwb_png_text *texts, int n_texts, char *err, size_t errlen);

int __wrap_uwb_condition_prepare(const struct uwb_scan *in, const struct uwb_geometry *g,
                                 const struct uwb_condition_options *opt, double dominant_hz,
                                 struct uwb_scan *out, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_condition_prepare(in, g, opt, dominant_hz, out, err, errlen);
    count(STAGE_CONDITION, t0, 0, 0);
    return rc;
}

int __wrap_uwb_condition_finish(const struct uwb_scan *prepared, const struct uwb_geometry *g,
                                const struct uwb_condition_options *opt, double dominant_hz,
                                const struct uwb_target_window *winding, struct uwb_scan *out, char *err,
                                size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_condition_finish(prepared, g, opt, dominant_hz, winding, out, err, errlen);
    count(STAGE_CONDITION, t0, 0, 0);
    return rc;
}

int __wrap_uwb_dominant_frequency(const struct uwb_scan *scan, double *hz, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_dominant_frequency(scan, hz, err, errlen);
    count(STAGE_DOMINANT, t0, 0, 0);
    return rc;
}

int __wrap_uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan,
                       const struct uwb_geometry *geom, struct uwb_image *img, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_migrate(kind, scan, geom, img, err, errlen);
    count(STAGE_MIGRATE, t0, img->ny, img->nz);
    totals.pixel_traces += (long long)img->ny * img->nz * scan->positions;
    return rc;
}

int __wrap_uwb_migration_plan_run(struct uwb_migration_plan *p, const struct uwb_scan *scan,
                                  const struct uwb_geometry *geom, struct uwb_image *img, char *err,
                                  size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_migration_plan_run(p, scan, geom, img, err, errlen);
    count(STAGE_MIGRATE, t0, img->ny, img->nz);
    totals.pixel_traces += (long long)img->ny * img->nz * scan->positions;
    return rc;
}

int __wrap_uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_envelope_along_z(img, err, errlen);
    count(STAGE_ENVELOPE, t0, img->ny, img->nz);
    return rc;
}

int __wrap_uwb_canvas_write_png(const struct uwb_canvas *c, const char *path,
                                const struct uwb_png_text *texts, int n_texts, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    int rc = __real_uwb_canvas_write_png(c, path, texts, n_texts, err, errlen);
    count(STAGE_PNG_ENCODE, t0, c->height, c->width);
    return rc;
}
