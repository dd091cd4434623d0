/*
 * candump.h - reading and writing the log format of `candump -l` (can-utils):
 *
 *   (1436509052.249713) vcan0 123#DEADBEEF          classic frame
 *   (1436509052.249713) vcan0 12345678#00           29-bit id (8 hex digits)
 *   (1436509052.249713) vcan0 123#R                 remote request (optional length digit)
 *   (1436509052.249713) vcan0 123##1112233          CAN FD: flags nibble, then data
 *   (1436509052.249713) vcan0 20000080#0000000000000000   error frame (CAN_ERR_FLAG in the id)
 *
 * Data bytes may be separated by '.' (between bytes only); a trailing
 * direction token (R or T, as newer candump versions write) is accepted.
 * The timestamp's fraction may have 1..9 digits; it is kept to the
 * microsecond (truncated). Frame sizes are exact: a classic frame 0..8
 * bytes, an FD frame 0..8, 12, 16, 20, 24, 32, 48 or 64 bytes, an error
 * frame 8 bytes, a remote request no data (an optional length digit 0..8).
 */
#ifndef GRIP_CANDUMP_H
#define GRIP_CANDUMP_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "grip/grip_can.h"

#define CANDUMP_IFNAME_MAX 32
#define CANDUMP_LINE_MAX 512

/* Parses one line (no line terminator needed). 0 on success, -1 with a
 * constant reason in *why. */
int candump_parse_line(const char *line, grip_can_frame_t *frame, char ifname[CANDUMP_IFNAME_MAX],
                       const char **why);

/* Formats a frame as a candump -l line with a trailing newline. Returns the
 * length, or -1 if buf is too small (CANDUMP_LINE_MAX always suffices). */
int candump_format(const grip_can_frame_t *frame, const char *ifname, char *buf, size_t len);

typedef struct {
    FILE *file;
    char path[512];
    unsigned long lineno;
    int skip_bad;            /* 1: skip malformed lines (counted) instead of failing */
    unsigned long skipped;   /* malformed lines skipped */
    unsigned long long offset;        /* bytes read so far */
    unsigned long long line_offset;   /* file offset of the current line's first byte */
    char line[CANDUMP_LINE_MAX + 2];
} candump_reader;

/* Opens a log ("-" is standard input). 0, or -1 with a message in err. */
int candump_open(candump_reader *r, const char *path, char *err, size_t errlen);

/* Next frame: 1 with *frame (and ifname if not NULL) filled, 0 at end of
 * file, -1 with "PATH:LINE: reason" (or a read error) in err.
 * Limits: a line holds at most CANDUMP_LINE_MAX bytes before its '\n'
 * (a longer one is an error also with skip_bad, without reading on); every
 * byte is printable ASCII, tab or CR (a candump log is ASCII text): a line
 * with any other byte (NUL, a control byte, a byte >= 0x80) is malformed,
 * reported with its byte offset in the file. Reading is streaming: memory
 * does not grow with the file. */
int candump_next(candump_reader *r, grip_can_frame_t *frame, char *ifname, char *err, size_t errlen);

void candump_close(candump_reader *r);

/* ---- frame order ----------------------------------------------------------
 * A log is in time order, up to a tolerance: candump writes frames as one
 * socket receives them, stamped by the kernel, so a log of one interface is
 * in order and one of several interfaces may be out of order by the time
 * between two reads (microseconds). candump_next_ordered passes frames on
 * in one of two modes:
 *   strict (window_us 0): a frame more than tolerance_us older than the
 *     newest frame before it is an error naming both lines and timestamps;
 *     smaller steps back are passed on as they are and counted.
 *   sorting (window_us > 0): frames are held back and passed on in time
 *     order (equal times in file order), each once no frame within
 *     window_us of it can follow; a frame more than window_us older than
 *     the newest frame before it, or more than max_frames frames waiting at
 *     once, is an error. Memory: max_frames entries, allocated by
 *     candump_order_init. */
#define CANDUMP_BACK_TOLERANCE_US 1000       /* default strict tolerance: 1 ms */
#define CANDUMP_REORDER_WINDOW_US 1000000    /* sorting window: 1 s */
#define CANDUMP_REORDER_MAX_FRAMES 65536     /* frames waiting at most (about 8 MB) */

typedef struct {
    grip_can_frame_t frame;
    unsigned long lineno;
    unsigned long seq;
    char ifname[CANDUMP_IFNAME_MAX];
} candump_pending;

typedef struct {
    int64_t tolerance_us;
    int64_t window_us;
    size_t max_frames;
    candump_pending *heap;        /* sorting: frames waiting, a min-heap on (time, seq) */
    size_t n;
    unsigned long seq;
    int have;                     /* a frame was read */
    int eof;
    int64_t newest_t;             /* the newest frame time read so far */
    unsigned long newest_line;    /* its line */
    unsigned long frames;         /* frames read */
    unsigned long out_of_order;   /* frames read older than the newest frame before them */
    int64_t max_back_us;          /* the largest such step back */
} candump_order;

/* 0, or -1 with a message in err (bad arguments, no memory). */
int candump_order_init(candump_order *o, int64_t tolerance_us, int64_t window_us, size_t max_frames, char *err,
                       size_t errlen);

/* As candump_next, in the order above. */
int candump_next_ordered(candump_reader *r, candump_order *o, grip_can_frame_t *frame, char *ifname, char *err,
                         size_t errlen);

void candump_order_free(candump_order *o);

/* Formats a time in microseconds as candump does ("SECONDS.UUUUUU"). */
void candump_format_time(int64_t t_us, char *buf, size_t len);

#endif /* GRIP_CANDUMP_H */
