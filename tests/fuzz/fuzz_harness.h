/* The fuzz harnesses: one function per parser that reads outside data.
 * Each feeds one input through its parser the way the program would and
 * checks the parser's contract:
 *   FUZZ_ACCEPTED  the parser took the input and what it produced is sane;
 *   FUZZ_REJECTED  the parser refused it and filled `why` with its message;
 *   FUZZ_BROKEN    the contract broke (a refusal without a message, an
 *                  accepted result out of its documented range, ...):
 *                  `why` says how.
 * The same functions run twice: under libFuzzer (tests/fuzz/fuzz_*.c
 * built by `make fuzz`, where FUZZ_BROKEN aborts so that libFuzzer keeps
 * the input), and over the committed corpora in `make test`
 * (tests/unit/test_fuzz_corpus.c), so a sanitizer build covers them too. */
#ifndef UWB_FUZZ_HARNESS_H
#define UWB_FUZZ_HARNESS_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

enum fuzz_outcome { FUZZ_ACCEPTED = 0, FUZZ_REJECTED = 1, FUZZ_BROKEN = -1 };

typedef int (*fuzz_harness_fn)(const uint8_t *data, size_t size, char *why, size_t whylen);

/* One per tests/fuzz/fuzz_<name>.c; the corpus is tests/fuzz/corpus/<name>/. */
int fuzz_scan_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_frame_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_digitiser_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_config_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_command_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_gpio_reply_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_gpio_board_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_analysis_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_state_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_set_input(const uint8_t *data, size_t size, char *why, size_t whylen);
int fuzz_ctl_reply_input(const uint8_t *data, size_t size, char *why, size_t whylen);

/* scripted_link.c: the links a harness's code under test opens (the
 * digitiser client, the emulated-GPIO backend) are socket pairs whose far
 * end has already said `data` and then closed its sending side; links
 * opened after the first one hear nothing (a board that went away). The
 * bytes the code under test writes are kept unread until the link closes.
 * fuzz_link_script(NULL, 0) after the input closes the far ends. Needs
 * the program linked with -Wl,--wrap=uwb_link_open. */
void fuzz_link_script(const uint8_t *data, size_t size);

/* frame_mutator.c: rewrites the CRCs of the digitiser frames in data, for
 * three seeds in four, so that mutated frames get past the CRC checks. */
void fuzz_fix_frame_crcs(uint8_t *data, size_t size, unsigned seed);

/* Writes a message into why and returns FUZZ_BROKEN. */
static inline int fuzz_broken(char *why, size_t whylen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static inline int fuzz_broken(char *why, size_t whylen, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, whylen, fmt, ap);
    va_end(ap);
    return FUZZ_BROKEN;
}

#ifdef UWB_LIBFUZZER
/* The libFuzzer entry point of a `make fuzz` binary: a broken contract
 * is a crash, with the reason on stderr. */
#define UWB_FUZZ_TARGET(harness) \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size); \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) \
    { \
        char why[1024] = ""; \
        if (harness(data, size, why, sizeof why) == FUZZ_BROKEN) { \
            fprintf(stderr, "fuzz contract broken: %s\n", why); \
            abort(); \
        } \
        return 0; \
    }
/* For the targets that read digitiser frames: libFuzzer's mutation, then
 * the CRCs made right again (most of the time). */
size_t LLVMFuzzerMutate(uint8_t *data, size_t size, size_t max_size);
#define UWB_FUZZ_FRAME_MUTATOR \
    size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size, unsigned seed); \
    size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size, unsigned seed) \
    { \
        size = LLVMFuzzerMutate(data, size, max_size); \
        fuzz_fix_frame_crcs(data, size, seed); \
        return size; \
    }
#else
#define UWB_FUZZ_TARGET(harness)
#define UWB_FUZZ_FRAME_MUTATOR
#endif

#endif
