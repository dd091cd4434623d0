/*
 * candump.h - reading and writing the log format of `candump -l` (can-utils):
 *
 *   (1436509052.249713) vcan0 123#DEADBEEF          classic frame
 *   (1436509052.249713) vcan0 12345678#00           29-bit id (8 hex digits)
 *   (1436509052.249713) vcan0 123#R                 remote request (optional length digit)
 *   (1436509052.249713) vcan0 123##1112233          CAN FD: flags nibble, then data
 *   (1436509052.249713) vcan0 20000080#0000000000000000   error frame (CAN_ERR_FLAG in the id)
 *
 * Data bytes may be separated by '.'; a trailing direction token (R or T,
 * as newer candump versions write) is accepted. The timestamp's fraction
 * may have 1..9 digits; it is kept to the microsecond (truncated).
 */
#ifndef GRIP_CANDUMP_H
#define GRIP_CANDUMP_H

#include <stddef.h>
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
    char line[CANDUMP_LINE_MAX + 2];
} candump_reader;

/* Opens a log ("-" is standard input). 0, or -1 with a message in err. */
int candump_open(candump_reader *r, const char *path, char *err, size_t errlen);

/* Next frame: 1 with *frame (and ifname if not NULL) filled, 0 at end of
 * file, -1 with "PATH:LINE: reason" (or a read error) in err. */
int candump_next(candump_reader *r, grip_can_frame_t *frame, char *ifname, char *err, size_t errlen);

void candump_close(candump_reader *r);

#endif /* GRIP_CANDUMP_H */
