/* uwbd's clock check under a syscall filter like a systemd unit's
 * (tests/e2e/test_clock_check_sandbox.sh):
 *   clock_check [--deny SYSCALL]... [--timesync-flag PATH]
 * installs a seccomp filter that fails each named syscall with EPERM, as
 * SystemCallFilter= with SystemCallErrorNumber=EPERM (or ProtectClock=)
 * does, then prints
 *   kernel: answered | refused: REASON   (ntp_adjtime, modes 0: read only)
 *   synchronised: 0 | 1                  (uwbd_clock_synchronised)
 *   how: WORDS                           (with --timesync-flag: the check
 *                                         with that flag file, and who said)
 * Names this architecture lacks (clock_adjtime64 on a 64-bit one) are
 * skipped. Exit 2 on a usage or seccomp error. */
#include <errno.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/timex.h>

#include "state/retention.h"

#define MAX_DENIED 16

struct named_syscall {
    const char *name;
    long nr;
};

/* The clock syscalls (systemd's @clock) this architecture has. */
static const struct named_syscall clock_syscalls[] = {
#ifdef SYS_adjtimex
    {"adjtimex", SYS_adjtimex},
#endif
#ifdef SYS_clock_adjtime
    {"clock_adjtime", SYS_clock_adjtime},
#endif
#ifdef SYS_clock_adjtime64
    {"clock_adjtime64", SYS_clock_adjtime64},
#endif
#ifdef SYS_clock_settime
    {"clock_settime", SYS_clock_settime},
#endif
#ifdef SYS_clock_settime64
    {"clock_settime64", SYS_clock_settime64},
#endif
#ifdef SYS_settimeofday
    {"settimeofday", SYS_settimeofday},
#endif
};

#if defined(__x86_64__)
#define NATIVE_ARCH AUDIT_ARCH_X86_64
#elif defined(__aarch64__)
#define NATIVE_ARCH AUDIT_ARCH_AARCH64
#elif defined(__arm__)
#define NATIVE_ARCH AUDIT_ARCH_ARM
#elif defined(__i386__)
#define NATIVE_ARCH AUDIT_ARCH_I386
#endif

static int deny(const long *nrs, int count)
{
    struct sock_filter f[8 + 2 * MAX_DENIED];
    int n = 0;
#ifdef NATIVE_ARCH
    /* Another architecture's numbers mean other syscalls: let them be. */
    f[n++] = (struct sock_filter)BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, arch));
    f[n++] = (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, NATIVE_ARCH, 1, 0);
    f[n++] = (struct sock_filter)BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);
#endif
    f[n++] = (struct sock_filter)BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, nr));
    for (int i = 0; i < count; i++) {
        f[n++] = (struct sock_filter)BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, (unsigned)nrs[i], 0, 1);
        f[n++] =
            (struct sock_filter)BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | (EPERM & SECCOMP_RET_DATA));
    }
    f[n++] = (struct sock_filter)BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);
    struct sock_fprog prog = {.len = (unsigned short)n, .filter = f};
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 ||
        prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &prog) != 0) {
        fprintf(stderr, "clock_check: cannot install the syscall filter: %s\n", strerror(errno));
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    long nrs[MAX_DENIED];
    int count = 0;
    const char *flag = NULL;
    for (int i = 1; i < argc; i++) {
        if (i + 1 < argc && strcmp(argv[i], "--timesync-flag") == 0) {
            flag = argv[++i];
            continue;
        }
        if (strcmp(argv[i], "--deny") != 0 || i + 1 == argc) {
            fprintf(stderr, "usage: clock_check [--deny SYSCALL]... [--timesync-flag PATH]\n");
            return 2;
        }
        const char *name = argv[++i];
        for (size_t k = 0; k < sizeof clock_syscalls / sizeof clock_syscalls[0]; k++)
            if (strcmp(clock_syscalls[k].name, name) == 0 && count < MAX_DENIED)
                nrs[count++] = clock_syscalls[k].nr;
    }
    if (count > 0 && deny(nrs, count) != 0)
        return 2;
    struct timex t;
    memset(&t, 0, sizeof t);
    if (ntp_adjtime(&t) < 0)
        printf("kernel: refused: %s\n", strerror(errno));
    else
        printf("kernel: answered\n");
    if (!flag) {
        printf("synchronised: %d\n", uwbd_clock_synchronised());
        return 0;
    }
    const char *how = NULL;
    printf("synchronised: %d\n", uwbd_clock_synchronised_from(flag, &how));
    printf("how: %s\n", how);
    return 0;
}
