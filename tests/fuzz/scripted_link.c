/* A scripted peer for the code that reads a board's byte stream through
 * uwb_link_open() (the digitiser client, the emulated-GPIO backend):
 * linked with -Wl,--wrap=uwb_link_open, every open gets one end of a
 * socket pair whose other end has already sent the fuzz input and shut its
 * sending side. The code under test reads through the real socket link
 * (uwb_link_from_fd), so a reply that never comes is an end of stream at
 * once, not a timeout. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "fuzz_harness.h"
#include "uwb/link.h"

/* A socket pair's buffer holds this much without blocking on Linux
 * (net.core.wmem_default is larger); longer inputs are cut here. */
#define SCRIPT_MAX (64 * 1024)
/* Far ends kept open until their link closes, so the code under test
 * can write its commands without meeting a closed peer. */
#define PEERS_MAX 64

static const uint8_t *script_data;
static size_t script_size;
static unsigned opens;
static int peers[PEERS_MAX];
static unsigned peer_count;

int __wrap_uwb_link_open(const char *endpoint, struct uwb_link **link, char *err, size_t errlen);

void fuzz_link_script(const uint8_t *data, size_t size)
{
    /* Far ends from the previous input: their links are closed by now. */
    for (unsigned i = 0; i < peer_count; i++)
        close(peers[i]);
    peer_count = 0;
    script_data = data;
    script_size = size;
    opens = 0;
}

int __wrap_uwb_link_open(const char *endpoint, struct uwb_link **link, char *err, size_t errlen)
{
    *link = NULL;
    int fds[2];
    if (peer_count == PEERS_MAX) {
        snprintf(err, errlen, "%s: fuzz peer: too many links opened for one input", endpoint);
        return UWB_LINK_ERR_OPEN;
    }
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
        snprintf(err, errlen, "%s: fuzz peer: socketpair: %s", endpoint, strerror(errno));
        return UWB_LINK_ERR_OPEN;
    }
    size_t n = opens == 0 ? script_size : 0;
    if (n > SCRIPT_MAX)
        n = SCRIPT_MAX;
    for (size_t sent = 0; sent < n;) {
        ssize_t w = send(fds[1], script_data + sent, n - sent, MSG_DONTWAIT | MSG_NOSIGNAL);
        if (w <= 0)
            break; /* the buffer is full: the rest is cut, as documented */
        sent += (size_t)w;
    }
    shutdown(fds[1], SHUT_WR);
    peers[peer_count++] = fds[1];
    opens++;
    return uwb_link_from_fd(fds[0], endpoint, link, err, errlen);
}
