/* Replies of the control protocol as text for people (src/text/): what
 * `uwbd ctl --text` and the serial console print. */
#ifndef UWB_REPLY_TEXT_H
#define UWB_REPLY_TEXT_H

#include <stdio.h>

/* The marks a terminal can show: "±" and "σ" in UTF-8, "+/-" and "sigma"
 * in ASCII (LC_ALL=C, a serial console). */
enum uwbd_charset {
    UWBD_CHARSET_UTF8,
    UWBD_CHARSET_ASCII,
};

/* The locale's: UTF8 where nl_langinfo(CODESET) is UTF-8, else ASCII.
 * Call setlocale(LC_CTYPE, "") first (LC_CTYPE only: LC_NUMERIC would
 * put decimal commas in the figures). */
enum uwbd_charset uwbd_charset_of_locale(void);

/* A VERDICT reply (one JSON line) as text for people: its time and scan
 * ("verdict of 2026-12-07T03:23:16Z, scan T3-north-uwb-..."), then
 * "status ALARM: displacement +12.04 ± 0.23 mm (edges ...)", or the
 * edges, or the reason; then "image: PATH" lines. -1, nothing printed, for any other reply. */
int uwbd_verdict_text(const char *reply, FILE *out);
int uwbd_verdict_text_in(const char *reply, FILE *out, enum uwbd_charset charset);

/* A TREND reply as a table: time, status, displacement ± 1 sigma, height
 * change, radial change and scan per verdict ("*" at a baseline change),
 * a reason wrapped under its row, never cut; then the rate and the image. -1, nothing printed, for any other
 * reply. */
int uwbd_trend_text(const char *reply, FILE *out);
int uwbd_trend_text_in(const char *reply, FILE *out, enum uwbd_charset charset);

/* Any reply line as text for people (uwbd ctl --text, the serial console):
 * a STATUS page of aligned "Name : value" lines, a HISTORY table, the HELP
 * list, a VERDICT and a TREND as above, a line for the short replies. -1,
 * nothing printed, when the line is not a reply (no "class"). */
int uwbd_reply_text(const char *reply, FILE *out);
/* The same in the charset given (the functions above write UTF-8). */
int uwbd_reply_text_in(const char *reply, FILE *out, enum uwbd_charset charset);

/* A PROGRESS reply's figures, read in one place for the console's line
 * and uwbd ctl's bar. pass and passes are 1 when the daemon sent none; the
 * has_ flags say which optional figures came. */
struct uwbd_progress {
    double position, positions;
    double pass, passes;
    int has_elapsed, has_left, has_fraction;
    double elapsed_s, left_s, fraction;
};

/* 0 and *p filled from a reply line carrying position and positions, else
 * -1 (not JSON, or either missing). */
int uwbd_progress_read(const char *reply, struct uwbd_progress *p);

#endif
