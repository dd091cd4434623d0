/*
 * can_socket.h - a SocketCAN raw socket for the estimator's inputs
 * (docs/can.md):
 *
 *  - kernel filters for exactly the configured ids (plus error frames,
 *    which are enabled and counted);
 *  - kernel receive timestamps (SO_TIMESTAMPNS, else SO_TIMESTAMP) read
 *    from recvmsg's control data;
 *  - drop counting from SO_RXQ_OVFL (frames the kernel discarded because
 *    the socket's receive queue was full);
 *  - classic CAN and CAN FD (CAN_RAW_FD_FRAMES) with exact size checks:
 *    a read must be exactly CAN_MTU or CANFD_MTU bytes;
 *  - interface state, bit rate and restart after bus-off through
 *    libsocketcan.
 */
#ifndef GRIP_CAN_SOCKET_H
#define GRIP_CAN_SOCKET_H

#include <stddef.h>
#include <stdint.h>

#include "grip/grip_can.h"

#define CAN_SOCK_MAX_IDS 64

/* Results of can_sock_read. */
enum {
    CAN_SOCK_FRAME = 1,     /* *frame filled (may be an error frame: GRIP_CAN_ID_ERR) */
    CAN_SOCK_TIMEOUT = 0,   /* nothing within the receive timeout */
    CAN_SOCK_ERROR = -1,    /* fatal socket error: message in err */
    CAN_SOCK_DOWN = -2,     /* the interface is down (ENETDOWN); retry later */
    CAN_SOCK_INTR = -3,     /* interrupted by a signal (EINTR) */
    CAN_SOCK_BAD = -4       /* a malformed read (truncated frame, bad length): counted, skip it */
};

typedef struct {
    int fd;
    char ifname[32];
    int fd_frames;              /* 1: CAN FD frames enabled */
    int ts_ns;                  /* 1: SO_TIMESTAMPNS, 0: SO_TIMESTAMP */
    int drop_reporting;         /* 1: SO_RXQ_OVFL is on */
    uint32_t drops;             /* frames dropped by the kernel since open */
    uint32_t frames;            /* frames read (data and error frames) */
    uint32_t error_frames;      /* error frames read */
    uint32_t bus_off;           /* error frames signalling bus-off */
    uint32_t controller_errors; /* error frames signalling controller problems (incl. overflows) */
    uint32_t truncated;         /* reads of a wrong size or with MSG_TRUNC */
    uint32_t interrupted;       /* EINTR */
    uint32_t down;              /* ENETDOWN */
    uint32_t no_timestamp;      /* frames without a kernel timestamp (clock used instead) */
} can_sock;

/* Opens a raw CAN socket on ifname, receiving only the given ids (table
 * keys: 11-bit, or 29-bit | GRIP_CAN_ID_EFF) and error frames; recv_timeout_ms
 * bounds each can_sock_read (0: block). want_fd enables CAN FD frames
 * (falls back to classic if the kernel refuses, with fd_frames = 0).
 * 0, or -1 with a message in err (e.g. "no CAN interface 'can0'"). */
int can_sock_open(can_sock *s, const char *ifname, const uint32_t *ids, size_t n_ids, int want_fd,
                  int recv_timeout_ms, char *err, size_t errlen);

/* Reads one frame (see the CAN_SOCK_* results). */
int can_sock_read(can_sock *s, grip_can_frame_t *frame, char *err, size_t errlen);

void can_sock_close(can_sock *s);

/* Interface state from libsocketcan ("error-active", "bus-off", ...;
 * "unknown" where the driver reports none, e.g. vcan) and bit rate (0 if
 * unknown). Returns 0 if the state was read, -1 otherwise. */
int can_sock_state(const char *ifname, char *state, size_t len, uint32_t *bitrate);

/* Restarts a controller after bus-off (libsocketcan can_do_restart; needs
 * CAP_NET_ADMIN). 0, or -1 with a message in err. */
int can_sock_restart(const char *ifname, char *err, size_t errlen);

#endif /* GRIP_CAN_SOCKET_H */
