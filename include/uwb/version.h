/* The software's version: in the daemon's log and replies, and in every
 * image and man page it writes. */
#ifndef UWB_VERSION_H
#define UWB_VERSION_H

#define UWBD_VERSION "0.1.0"

#endif
