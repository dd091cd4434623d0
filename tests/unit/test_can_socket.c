/* LDFLAGS: -lsocketcan -Wl,--wrap=socket -Wl,--wrap=bind -Wl,--wrap=setsockopt -Wl,--wrap=recvmsg -Wl,--wrap=close -Wl,--wrap=if_nametoindex -Wl,--wrap=can_get_state -Wl,--wrap=can_get_bittiming -Wl,--wrap=can_do_restart */
/*
 * test_can_socket.c - the SocketCAN layer (port/linux/can_socket.c) with the
 * kernel mocked: socket, bind, setsockopt, recvmsg, close, if_nametoindex
 * and libsocketcan's state/bit-timing/restart calls are replaced at link
 * time (-Wl,--wrap, see the LDFLAGS line above) by the fakes below. Covers
 * the filters and options set, classic and FD frames, kernel timestamps,
 * drop counts, truncated and oversized reads, EINTR, EAGAIN, ENETDOWN, other
 * errors, error frames (bus-off), a missing interface and bus-off restart.
 */
#define _DEFAULT_SOURCE 1
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <errno.h>
#include <time.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <libsocketcan.h>
#include <cmocka.h>

#include "can_socket.h"

/* ---- fakes ---------------------------------------------------------------------- */

#define FAKE_FD 42

static struct {
    unsigned ifindex;          /* 0: no such interface */
    int socket_errno;          /* socket() fails with this */
    int bind_errno;
    int fail_level, fail_opt;  /* setsockopt(level, opt) fails with fail_errno */
    int fail_errno;
    struct can_filter filters[CAN_SOCK_MAX_IDS];
    int n_filters;
    can_err_mask_t err_mask;
    int fd_on, tsns_on, ts_on, ovfl_on, rcvtimeo_ms;
    int closed;
    int state;                 /* can_get_state: -1 fails */
    int restart_rc;
    int restarts;
} k;

/* One scripted recvmsg result. */
typedef struct {
    int err;                   /* errno, or 0 */
    ssize_t n;                 /* bytes returned */
    int trunc;                 /* MSG_TRUNC in msg_flags */
    struct canfd_frame frame;
    int ts;                    /* 1: SCM_TIMESTAMPNS, 2: SCM_TIMESTAMP, 0: none */
    int64_t t_ns;
    int drops;                 /* <0: no SO_RXQ_OVFL */
} fake_read;

static fake_read script[8];
static int n_script;
static int next_read;

int __wrap_if_nametoindex(const char *name);
int __wrap_socket(int domain, int type, int protocol);
int __wrap_setsockopt(int fd, int level, int opt, const void *val, socklen_t len);
int __wrap_bind(int fd, const struct sockaddr *addr, socklen_t len);
ssize_t __wrap_recvmsg(int fd, struct msghdr *msg, int flags);
int __wrap_close(int fd);
int __wrap_can_get_state(const char *name, int *state);
int __wrap_can_get_bittiming(const char *name, struct can_bittiming *bt);
int __wrap_can_do_restart(const char *name);

int __wrap_if_nametoindex(const char *name)
{
    (void)name;
    if (k.ifindex == 0) {
        errno = ENODEV;
    }
    return (int)k.ifindex;
}

int __wrap_socket(int domain, int type, int protocol)
{
    assert_int_equal(domain, PF_CAN);
    assert_int_equal(type, SOCK_RAW);
    assert_int_equal(protocol, CAN_RAW);
    if (k.socket_errno) {
        errno = k.socket_errno;
        return -1;
    }
    return FAKE_FD;
}

int __wrap_setsockopt(int fd, int level, int opt, const void *val, socklen_t len)
{
    assert_int_equal(fd, FAKE_FD);
    if (level == k.fail_level && opt == k.fail_opt) {
        errno = k.fail_errno;
        return -1;
    }
    if (level == SOL_CAN_RAW && opt == CAN_RAW_FILTER) {
        k.n_filters = (int)(len / sizeof(struct can_filter));
        if (k.n_filters > 0) {
            memcpy(k.filters, val, len);
        }
    } else if (level == SOL_CAN_RAW && opt == CAN_RAW_ERR_FILTER) {
        memcpy(&k.err_mask, val, sizeof k.err_mask);
    } else if (level == SOL_CAN_RAW && opt == CAN_RAW_FD_FRAMES) {
        k.fd_on = *(const int *)val;
    } else if (level == SOL_SOCKET && opt == SO_TIMESTAMPNS) {
        k.tsns_on = *(const int *)val;
    } else if (level == SOL_SOCKET && opt == SO_TIMESTAMP) {
        k.ts_on = *(const int *)val;
    } else if (level == SOL_SOCKET && opt == SO_RXQ_OVFL) {
        k.ovfl_on = *(const int *)val;
    } else if (level == SOL_SOCKET && opt == SO_RCVTIMEO) {
        const struct timeval *tv = val;
        k.rcvtimeo_ms = (int)(tv->tv_sec * 1000 + tv->tv_usec / 1000);
    } else {
        fail_msg("unexpected setsockopt(%d, %d)", level, opt);
    }
    return 0;
}

int __wrap_bind(int fd, const struct sockaddr *addr, socklen_t len)
{
    const struct sockaddr_can *a = (const struct sockaddr_can *)(const void *)addr;
    assert_int_equal(fd, FAKE_FD);
    assert_int_equal(len, sizeof(struct sockaddr_can));
    assert_int_equal(a->can_family, AF_CAN);
    assert_int_equal(a->can_ifindex, (int)k.ifindex);
    if (k.bind_errno) {
        errno = k.bind_errno;
        return -1;
    }
    return 0;
}

ssize_t __wrap_recvmsg(int fd, struct msghdr *msg, int flags)
{
    const fake_read *r;
    struct cmsghdr *cm;
    size_t used = 0;
    assert_int_equal(fd, FAKE_FD);
    assert_int_equal(flags, 0);
    assert_true(next_read < n_script);
    r = &script[next_read++];
    if (r->err) {
        errno = r->err;
        return -1;
    }
    assert_true(msg->msg_iovlen == 1 && msg->msg_iov[0].iov_len >= (size_t)r->n);
    memcpy(msg->msg_iov[0].iov_base, &r->frame, (size_t)r->n);
    msg->msg_flags = r->trunc ? MSG_TRUNC : 0;
    cm = CMSG_FIRSTHDR(msg);
    if (r->ts == 1) {
        struct timespec ts = { (time_t)(r->t_ns / 1000000000), (long)(r->t_ns % 1000000000) };
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_TIMESTAMPNS;
        cm->cmsg_len = CMSG_LEN(sizeof ts);
        memcpy(CMSG_DATA(cm), &ts, sizeof ts);
        used += CMSG_SPACE(sizeof ts);
        cm = (struct cmsghdr *)(void *)((char *)msg->msg_control + used);
    } else if (r->ts == 2) {
        struct timeval tv = { (time_t)(r->t_ns / 1000000000), (suseconds_t)(r->t_ns % 1000000000 / 1000) };
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_TIMESTAMP;
        cm->cmsg_len = CMSG_LEN(sizeof tv);
        memcpy(CMSG_DATA(cm), &tv, sizeof tv);
        used += CMSG_SPACE(sizeof tv);
        cm = (struct cmsghdr *)(void *)((char *)msg->msg_control + used);
    }
    if (r->drops >= 0) {
        uint32_t d = (uint32_t)r->drops;
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SO_RXQ_OVFL;
        cm->cmsg_len = CMSG_LEN(sizeof d);
        memcpy(CMSG_DATA(cm), &d, sizeof d);
        used += CMSG_SPACE(sizeof d);
    }
    assert_true(used <= msg->msg_controllen);
    msg->msg_controllen = used;
    return r->n;
}

int __real_close(int fd);

int __wrap_close(int fd)
{
    if (fd != FAKE_FD) {
        return __real_close(fd);   /* not the socket (stderr muting in can_sock_state) */
    }
    k.closed++;
    return 0;
}

int __wrap_can_get_state(const char *name, int *state)
{
    (void)name;
    if (k.state < 0) {
        return -1;
    }
    *state = k.state;
    return 0;
}

int __wrap_can_get_bittiming(const char *name, struct can_bittiming *bt)
{
    (void)name;
    bt->bitrate = 500000;
    return 0;
}

int __wrap_can_do_restart(const char *name)
{
    (void)name;
    k.restarts++;
    return k.restart_rc;
}

/* ---- helpers ------------------------------------------------------------------------ */

static const uint32_t IDS[3] = { 0x024u, 0x0B4u, 0x18FF0001u | GRIP_CAN_ID_EFF };

static int reset(void **state)
{
    (void)state;
    memset(&k, 0, sizeof k);
    k.ifindex = 7;
    k.fail_level = -1;
    memset(script, 0, sizeof script);
    n_script = 0;
    next_read = 0;
    return 0;
}

static fake_read *add_read(uint32_t id, int len, ssize_t n)
{
    fake_read *r = &script[n_script++];
    int i;
    r->n = n;
    r->frame.can_id = id;
    r->frame.len = (uint8_t)len;
    for (i = 0; i < len && i < 64; i++) {
        r->frame.data[i] = (uint8_t)(0x10 + i);
    }
    r->ts = 1;
    r->t_ns = 1700000000123456789LL;
    r->drops = 0;
    return r;
}

static void open_ok(can_sock *s, int want_fd)
{
    char err[300] = "";
    if (can_sock_open(s, "vcan0", IDS, 3, want_fd, 50, err, sizeof err) != 0) {
        fail_msg("open failed: %s", err);
    }
}

/* ---- tests ------------------------------------------------------------------------------ */

static void test_open_sets_filters_and_options(void **state)
{
    can_sock s;
    (void)state;
    open_ok(&s, 1);
    assert_int_equal(k.n_filters, 3);
    assert_int_equal(k.filters[0].can_id, 0x024);
    assert_int_equal(k.filters[0].can_mask, CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_SFF_MASK);
    assert_int_equal(k.filters[1].can_id, 0x0B4);
    assert_int_equal(k.filters[2].can_id, 0x18FF0001u | CAN_EFF_FLAG);
    assert_int_equal(k.filters[2].can_mask, CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_EFF_MASK);
    assert_int_equal(k.err_mask, CAN_ERR_MASK);
    assert_int_equal(k.fd_on, 1);
    assert_int_equal(s.fd_frames, 1);
    assert_int_equal(k.tsns_on, 1);
    assert_int_equal(s.ts_ns, 1);
    assert_int_equal(k.ovfl_on, 1);
    assert_int_equal(k.rcvtimeo_ms, 50);
    can_sock_close(&s);
    assert_int_equal(k.closed, 1);
}

static void test_open_errors_are_clear(void **state)
{
    can_sock s;
    char err[300];
    (void)state;
    k.ifindex = 0;
    assert_int_equal(can_sock_open(&s, "can9", IDS, 3, 0, 50, err, sizeof err), -1);
    assert_string_equal(err, "no CAN interface 'can9' (No such device)");
    reset(NULL);
    k.socket_errno = EAFNOSUPPORT;
    assert_int_equal(can_sock_open(&s, "vcan0", IDS, 3, 0, 50, err, sizeof err), -1);
    assert_non_null(strstr(err, "kernel without CAN"));
    reset(NULL);
    k.bind_errno = ENETDOWN;
    assert_int_equal(can_sock_open(&s, "vcan0", IDS, 3, 0, 50, err, sizeof err), -1);
    assert_non_null(strstr(err, "vcan0 is down"));
    assert_int_equal(k.closed, 1);
    reset(NULL);
    k.fail_level = SOL_CAN_RAW;
    k.fail_opt = CAN_RAW_FILTER;
    k.fail_errno = EINVAL;
    assert_int_equal(can_sock_open(&s, "vcan0", IDS, 3, 0, 50, err, sizeof err), -1);
    assert_non_null(strstr(err, "id filters"));
    assert_int_equal(k.closed, 1);
    reset(NULL);
    assert_int_equal(can_sock_open(&s, "a-name-longer-than-ifnamsiz", IDS, 3, 0, 50, err, sizeof err), -1);
    assert_non_null(strstr(err, "bad CAN interface name"));
}

static void test_fd_refused_falls_back_and_old_timestamps(void **state)
{
    can_sock s;
    grip_can_frame_t f;
    char err[300];
    fake_read *r;
    (void)state;
    k.fail_level = SOL_SOCKET;
    k.fail_opt = SO_TIMESTAMPNS;
    k.fail_errno = ENOPROTOOPT;
    open_ok(&s, 1);
    assert_int_equal(s.ts_ns, 0);
    assert_int_equal(k.ts_on, 1);
    reset(NULL);
    k.fail_level = SOL_CAN_RAW;
    k.fail_opt = CAN_RAW_FD_FRAMES;
    k.fail_errno = ENOPROTOOPT;
    open_ok(&s, 1);
    assert_int_equal(s.fd_frames, 0);
    /* without FD enabled, a 72-byte read is not a frame */
    r = add_read(0x24, 8, CANFD_MTU);
    (void)r;
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_BAD);
    assert_non_null(strstr(err, "72 bytes (expected 16)"));
    assert_int_equal(s.truncated, 1);
}

static void test_read_classic_fd_timestamps_and_drops(void **state)
{
    can_sock s;
    grip_can_frame_t f;
    char err[300];
    fake_read *r;
    (void)state;
    open_ok(&s, 1);
    r = add_read(0x0B4, 8, CAN_MTU);
    r->drops = 3;
    r = add_read(0x18FF0001u | CAN_EFF_FLAG, 12, CANFD_MTU);
    r->frame.flags = CANFD_BRS;
    r->ts = 2;
    r->t_ns = 1700000001000002000LL;
    r->drops = 5;
    r = add_read(0x024, 2, CAN_MTU);
    r->ts = 0;
    r->drops = -1;
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(f.id, 0x0B4);
    assert_int_equal(f.len, 8);
    assert_int_equal(f.flags, 0);
    assert_int_equal(f.data[7], 0x17);
    assert_true(f.t_us == 1700000000123456LL);
    assert_int_equal(s.drops, 3);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(f.id, 0x18FF0001u | GRIP_CAN_ID_EFF);
    assert_int_equal(f.len, 12);
    assert_int_equal(f.flags, GRIP_CAN_FLAG_FD | GRIP_CAN_FLAG_BRS);
    assert_int_equal(f.data[11], 0x1B);
    assert_true(f.t_us == 1700000001000002LL);
    assert_int_equal(s.drops, 5);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(s.no_timestamp, 1);
    assert_true(f.t_us > 1600000000000000LL);   /* the clock stands in */
    assert_int_equal(s.drops, 5);               /* no report: unchanged */
    assert_int_equal(s.frames, 3);
}

static void test_truncated_and_impossible_reads(void **state)
{
    can_sock s;
    grip_can_frame_t f;
    char err[300];
    fake_read *r;
    (void)state;
    open_ok(&s, 1);
    add_read(0x024, 8, 10);                      /* short read */
    r = add_read(0x024, 8, CAN_MTU);
    r->trunc = 1;                                /* the kernel cut the datagram */
    add_read(0x024, 9, CAN_MTU);                 /* classic frame claiming 9 bytes */
    add_read(0x024, 65, CANFD_MTU);              /* FD frame claiming 65 bytes */
    add_read(0x024, 8, CAN_MTU);                 /* and a good one after them */
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_BAD);
    assert_non_null(strstr(err, "10 bytes (expected 16 or 72)"));
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_BAD);
    assert_non_null(strstr(err, "MSG_TRUNC"));
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_BAD);
    assert_non_null(strstr(err, "impossible payload length 9"));
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_BAD);
    assert_int_equal(s.truncated, 4);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(f.len, 8);
    assert_int_equal(s.frames, 1);
}

static void test_errno_results(void **state)
{
    can_sock s;
    grip_can_frame_t f;
    char err[300];
    (void)state;
    open_ok(&s, 0);
    script[n_script++].err = EINTR;
    script[n_script++].err = EAGAIN;
    script[n_script++].err = ENETDOWN;
    add_read(0x024, 8, CAN_MTU);                 /* the interface came back */
    script[n_script++].err = EBADF;
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_INTR);
    assert_int_equal(s.interrupted, 1);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_TIMEOUT);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_DOWN);
    assert_string_equal(err, "CAN interface vcan0 is down");
    assert_int_equal(s.down, 1);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_ERROR);
    assert_non_null(strstr(err, "cannot read from vcan0: Bad file descriptor"));
}

static void test_bus_off_error_frame_state_and_restart(void **state)
{
    can_sock s;
    grip_can_frame_t f;
    char err[300];
    char st[32];
    uint32_t bitrate = 0;
    (void)state;
    open_ok(&s, 0);
    add_read(CAN_ERR_FLAG | CAN_ERR_BUSOFF | CAN_ERR_CRTL, CAN_ERR_DLC, CAN_MTU);
    assert_int_equal(can_sock_read(&s, &f, err, sizeof err), CAN_SOCK_FRAME);
    assert_int_equal(f.id & GRIP_CAN_ID_ERR, GRIP_CAN_ID_ERR);
    assert_int_equal(s.error_frames, 1);
    assert_int_equal(s.bus_off, 1);
    assert_int_equal(s.controller_errors, 1);
    k.state = CAN_STATE_BUS_OFF;
    assert_int_equal(can_sock_state("vcan0", st, sizeof st, &bitrate), 0);
    assert_string_equal(st, "bus-off");
    assert_int_equal(bitrate, 500000);
    k.state = -1;   /* vcan has no state */
    assert_int_equal(can_sock_state("vcan0", st, sizeof st, NULL), -1);
    assert_string_equal(st, "unknown");
    k.restart_rc = 0;
    assert_int_equal(can_sock_restart("can0", err, sizeof err), 0);
    k.restart_rc = -1;
    assert_int_equal(can_sock_restart("can0", err, sizeof err), -1);
    assert_non_null(strstr(err, "cannot restart can0 after bus-off"));
    assert_int_equal(k.restarts, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_open_sets_filters_and_options, reset),
        cmocka_unit_test_setup(test_open_errors_are_clear, reset),
        cmocka_unit_test_setup(test_fd_refused_falls_back_and_old_timestamps, reset),
        cmocka_unit_test_setup(test_read_classic_fd_timestamps_and_drops, reset),
        cmocka_unit_test_setup(test_truncated_and_impossible_reads, reset),
        cmocka_unit_test_setup(test_errno_results, reset),
        cmocka_unit_test_setup(test_bus_off_error_frame_state_and_restart, reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
