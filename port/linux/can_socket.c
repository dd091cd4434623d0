/*
 * can_socket.c - SocketCAN raw socket with kernel filters, timestamps, drop
 * counting, CAN FD and libsocketcan interface control (can_socket.h).
 */
/* SO_RXQ_OVFL, SCM_TIMESTAMP(NS): Linux socket options outside POSIX. */
#define _DEFAULT_SOURCE 1

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/uio.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <libsocketcan.h>

#include "can_socket.h"

/* The frame id flags of grip_can.h are Linux's. */
typedef char can_sock_check_eff[(GRIP_CAN_ID_EFF == CAN_EFF_FLAG) ? 1 : -1];
typedef char can_sock_check_rtr[(GRIP_CAN_ID_RTR == CAN_RTR_FLAG) ? 1 : -1];
typedef char can_sock_check_err[(GRIP_CAN_ID_ERR == CAN_ERR_FLAG) ? 1 : -1];

static void fail(char *err, size_t errlen, const char *what, const char *ifname, int e)
{
    snprintf(err, errlen, "%s %s: %s", what, ifname, strerror(e));
}

int can_sock_open(can_sock *s, const char *ifname, const uint32_t *ids, size_t n_ids, int want_fd,
                  int recv_timeout_ms, char *err, size_t errlen)
{
    struct sockaddr_can addr;
    struct can_filter filters[CAN_SOCK_MAX_IDS];
    can_err_mask_t errmask = CAN_ERR_MASK;
    int on = 1;
    unsigned idx;
    size_t i;
    int fd;

    memset(s, 0, sizeof *s);
    s->fd = -1;
    if (ifname == NULL || ifname[0] == '\0' || strlen(ifname) >= IF_NAMESIZE || strlen(ifname) >= sizeof s->ifname) {
        snprintf(err, errlen, "bad CAN interface name '%s'", ifname ? ifname : "");
        return -1;
    }
    if (n_ids > CAN_SOCK_MAX_IDS || (n_ids > 0 && ids == NULL)) {
        snprintf(err, errlen, "too many CAN ids for the kernel filter (%zu > %d)", n_ids, CAN_SOCK_MAX_IDS);
        return -1;
    }
    snprintf(s->ifname, sizeof s->ifname, "%s", ifname);
    errno = 0;
    idx = if_nametoindex(ifname);
    if (idx == 0) {
        snprintf(err, errlen, "no CAN interface '%s' (%s)", ifname, strerror(errno ? errno : ENODEV));
        return -1;
    }
    fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        int e = errno;
        snprintf(err, errlen, "cannot open a raw CAN socket: %s (kernel without CAN, or can-raw not loaded?)",
                 strerror(e));
        return -1;
    }
    for (i = 0; i < n_ids; i++) {
        if ((ids[i] & GRIP_CAN_ID_EFF) != 0u) {
            filters[i].can_id = (ids[i] & CAN_EFF_MASK) | CAN_EFF_FLAG;
            filters[i].can_mask = CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_EFF_MASK;
        } else {
            filters[i].can_id = ids[i] & CAN_SFF_MASK;
            filters[i].can_mask = CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_SFF_MASK;
        }
    }
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, n_ids ? (void *)filters : NULL,
                   (socklen_t)(n_ids * sizeof filters[0])) != 0) {
        fail(err, errlen, "cannot set the id filters on", ifname, errno);
        close(fd);
        return -1;
    }
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errmask, sizeof errmask) != 0) {
        fail(err, errlen, "cannot enable error frames on", ifname, errno);
        close(fd);
        return -1;
    }
    if (want_fd) {
        s->fd_frames = setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) == 0;
    }
    if (setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) == 0) {
        s->ts_ns = 1;
    } else if (setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0) {
        fail(err, errlen, "cannot enable receive timestamps on", ifname, errno);
        close(fd);
        return -1;
    }
    if (setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0) {
        fail(err, errlen, "cannot enable drop counting (SO_RXQ_OVFL) on", ifname, errno);
        close(fd);
        return -1;
    }
    s->drop_reporting = 1;
    if (recv_timeout_ms > 0) {
        struct timeval tv;
        tv.tv_sec = recv_timeout_ms / 1000;
        tv.tv_usec = (recv_timeout_ms % 1000) * 1000;
        if (setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv) != 0) {
            fail(err, errlen, "cannot set the receive timeout on", ifname, errno);
            close(fd);
            return -1;
        }
    }
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        int e = errno;
        if (e == ENETDOWN) {
            snprintf(err, errlen, "CAN interface %s is down (ip link set %s up)", ifname, ifname);
        } else {
            fail(err, errlen, "cannot bind to", ifname, e);
        }
        close(fd);
        return -1;
    }
    s->fd = fd;
    return 0;
}

int can_sock_read(can_sock *s, grip_can_frame_t *frame, char *err, size_t errlen)
{
    struct canfd_frame cf;
    struct iovec iov;
    struct msghdr msg;
    struct cmsghdr *cm;
    union {
        char buf[CMSG_SPACE(sizeof(struct timespec)) + CMSG_SPACE(sizeof(uint32_t)) + 64];
        struct cmsghdr align;
    } ctrl;
    ssize_t n;
    int have_ts = 0;

    memset(frame, 0, sizeof *frame);
    memset(&cf, 0, sizeof cf);
    memset(&msg, 0, sizeof msg);
    iov.iov_base = &cf;
    iov.iov_len = sizeof cf;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = ctrl.buf;
    msg.msg_controllen = sizeof ctrl.buf;
    n = recvmsg(s->fd, &msg, 0);
    if (n < 0) {
        int e = errno;
        if (e == EAGAIN || e == EWOULDBLOCK) {
            return CAN_SOCK_TIMEOUT;
        }
        if (e == EINTR) {
            s->interrupted++;
            return CAN_SOCK_INTR;
        }
        if (e == ENETDOWN) {
            s->down++;
            snprintf(err, errlen, "CAN interface %s is down", s->ifname);
            return CAN_SOCK_DOWN;
        }
        fail(err, errlen, "cannot read from", s->ifname, e);
        return CAN_SOCK_ERROR;
    }
    if ((msg.msg_flags & MSG_TRUNC) != 0 || (n != (ssize_t)CAN_MTU && !(s->fd_frames && n == (ssize_t)CANFD_MTU))) {
        s->truncated++;
        snprintf(err, errlen, "%s: truncated or oversized frame of %zd bytes (expected %d%s)%s", s->ifname, n,
                 (int)CAN_MTU, s->fd_frames ? " or 72" : "", (msg.msg_flags & MSG_TRUNC) ? " [MSG_TRUNC]" : "");
        return CAN_SOCK_BAD;
    }
    if ((n == (ssize_t)CAN_MTU && cf.len > CAN_MAX_DLEN) || cf.len > CANFD_MAX_DLEN) {
        s->truncated++;
        snprintf(err, errlen, "%s: frame with impossible payload length %u", s->ifname, (unsigned)cf.len);
        return CAN_SOCK_BAD;
    }
    for (cm = CMSG_FIRSTHDR(&msg); cm != NULL; cm = CMSG_NXTHDR(&msg, cm)) {
        if (cm->cmsg_level != SOL_SOCKET) {
            continue;
        }
        if (cm->cmsg_type == SCM_TIMESTAMPNS && cm->cmsg_len >= CMSG_LEN(sizeof(struct timespec))) {
            struct timespec ts;
            memcpy(&ts, CMSG_DATA(cm), sizeof ts);
            frame->t_us = (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
            have_ts = 1;
        } else if (cm->cmsg_type == SCM_TIMESTAMP && cm->cmsg_len >= CMSG_LEN(sizeof(struct timeval))) {
            struct timeval tv;
            memcpy(&tv, CMSG_DATA(cm), sizeof tv);
            frame->t_us = (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
            have_ts = 1;
        } else if (cm->cmsg_type == SO_RXQ_OVFL && cm->cmsg_len >= CMSG_LEN(sizeof(uint32_t))) {
            uint32_t d;
            memcpy(&d, CMSG_DATA(cm), sizeof d);
            s->drops = d;
        }
    }
    if (!have_ts) {
        struct timespec now;
        clock_gettime(CLOCK_REALTIME, &now);
        frame->t_us = (int64_t)now.tv_sec * 1000000 + now.tv_nsec / 1000;
        s->no_timestamp++;
    }
    frame->id = cf.can_id;
    frame->len = cf.len;
    memcpy(frame->data, cf.data, cf.len);
    if (n == (ssize_t)CANFD_MTU) {
        frame->flags = (uint8_t)(GRIP_CAN_FLAG_FD | ((cf.flags & CANFD_BRS) ? GRIP_CAN_FLAG_BRS : 0u) |
                                 ((cf.flags & CANFD_ESI) ? GRIP_CAN_FLAG_ESI : 0u));
    }
    s->frames++;
    if ((cf.can_id & CAN_ERR_FLAG) != 0u) {
        s->error_frames++;
        if ((cf.can_id & CAN_ERR_BUSOFF) != 0u) {
            s->bus_off++;
        }
        if ((cf.can_id & CAN_ERR_CRTL) != 0u) {
            s->controller_errors++;
        }
    }
    return CAN_SOCK_FRAME;
}

void can_sock_close(can_sock *s)
{
    if (s->fd >= 0) {
        close(s->fd);
    }
    s->fd = -1;
}

/* libsocketcan prints "no link data found" on stderr for interfaces
 * without CAN link data (vcan): not an error here, so its stderr is muted
 * around the calls. */
static int mute_stderr(void)
{
    int saved;
    int null;
    fflush(stderr);
    saved = dup(2);
    null = open("/dev/null", O_WRONLY);
    if (saved >= 0 && null >= 0) {
        dup2(null, 2);
    }
    if (null >= 0) {
        close(null);
    }
    return saved;
}

static void unmute_stderr(int saved)
{
    if (saved >= 0) {
        fflush(stderr);
        dup2(saved, 2);
        close(saved);
    }
}

int can_sock_state(const char *ifname, char *state, size_t len, uint32_t *bitrate)
{
    static const char *const NAMES[] = { "error-active", "error-warning", "error-passive", "bus-off",
                                         "stopped", "sleeping" };
    struct can_bittiming bt;
    int st = -1;
    int rc = 0;
    int got;
    int saved = mute_stderr();

    if (bitrate != NULL) {
        *bitrate = 0;
        memset(&bt, 0, sizeof bt);
        if (can_get_bittiming(ifname, &bt) == 0) {
            *bitrate = bt.bitrate;
        }
    }
    got = can_get_state(ifname, &st);
    unmute_stderr(saved);
    if (got != 0 || st < 0 || st >= (int)(sizeof NAMES / sizeof NAMES[0])) {
        snprintf(state, len, "unknown");
        rc = -1;
    } else {
        snprintf(state, len, "%s", NAMES[st]);
    }
    return rc;
}

int can_sock_restart(const char *ifname, char *err, size_t errlen)
{
    if (can_do_restart(ifname) != 0) {
        snprintf(err, errlen, "cannot restart %s after bus-off (libsocketcan can_do_restart failed: "
                 "it needs CAP_NET_ADMIN, a real controller and restart-ms 0)", ifname);
        return -1;
    }
    return 0;
}
