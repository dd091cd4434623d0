/*
 * candump.c - reading and writing `candump -l` logs (candump.h).
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "candump.h"

static int hexval(char c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Data bytes as hex pairs, optionally separated by '.', up to the first
 * blank or the end. Returns the byte count, or -1 (odd digit count, bad
 * digit, more than max bytes). */
static int parse_data(const char **pp, uint8_t *data, int max, const char **why)
{
    const char *p = *pp;
    int n = 0;
    while (*p != '\0' && !is_blank(*p) && *p != '_' && *p != '\r' && *p != '\n') {
        int hi;
        int lo;
        if (*p == '.') {
            p++;
            continue;
        }
        hi = hexval(p[0]);
        lo = (hi >= 0) ? hexval(p[1]) : -1;
        if (hi < 0 || lo < 0) {
            int ends = hi >= 0 && (p[1] == '\0' || is_blank(p[1]) || p[1] == '\r' || p[1] == '\n' ||
                                   p[1] == '.' || p[1] == '_');
            *why = ends ? "data: odd number of hex digits" : "data: not a hex digit";
            return -1;
        }
        if (n >= max) {
            *why = (max == 8) ? "data: more than 8 bytes in a classic frame (use ## for CAN FD)"
                              : "data: more than 64 bytes";
            return -1;
        }
        data[n++] = (uint8_t)(hi * 16 + lo);
        p += 2;
    }
    *pp = p;
    return n;
}

static int fd_len_ok(int n)
{
    return n <= 8 || n == 12 || n == 16 || n == 20 || n == 24 || n == 32 || n == 48 || n == 64;
}

int candump_parse_line(const char *line, grip_can_frame_t *frame, char ifname[CANDUMP_IFNAME_MAX],
                       const char **why)
{
    const char *p = line;
    int64_t sec = 0;
    int64_t frac = 0;
    int ndig = 0;
    int nfrac = 0;
    int n;
    int idlen = 0;
    uint32_t id = 0;
    const char *dummy;

    if (why == NULL) {
        why = &dummy;
    }
    *why = "";
    if (line == NULL || frame == NULL) {
        *why = "NULL argument";
        return -1;
    }
    memset(frame, 0, sizeof *frame);
    while (is_blank(*p)) {
        p++;
    }
    if (*p++ != '(') {
        *why = "expected '(' and a timestamp";
        return -1;
    }
    while (*p >= '0' && *p <= '9') {
        if (++ndig > 12) {
            *why = "timestamp: too many digits";
            return -1;
        }
        sec = sec * 10 + (*p++ - '0');
    }
    if (ndig == 0 || *p++ != '.') {
        *why = "timestamp: expected SECONDS.FRACTION";
        return -1;
    }
    while (*p >= '0' && *p <= '9') {
        if (++nfrac > 9) {
            *why = "timestamp: more than 9 fraction digits";
            return -1;
        }
        if (nfrac <= 6) {
            frac = frac * 10 + (*p - '0');
        }
        p++;
    }
    if (nfrac == 0 || *p++ != ')') {
        *why = "timestamp: expected SECONDS.FRACTION)";
        return -1;
    }
    for (n = nfrac; n < 6; n++) {
        frac *= 10;
    }
    frame->t_us = sec * 1000000 + frac;
    if (!is_blank(*p)) {
        *why = "expected a blank after the timestamp";
        return -1;
    }
    while (is_blank(*p)) {
        p++;
    }
    for (n = 0; *p != '\0' && !is_blank(*p); n++, p++) {
        if (n >= CANDUMP_IFNAME_MAX - 1) {
            *why = "interface name too long";
            return -1;
        }
        if (ifname != NULL) {
            ifname[n] = *p;
        }
    }
    if (ifname != NULL) {
        ifname[n < CANDUMP_IFNAME_MAX ? n : CANDUMP_IFNAME_MAX - 1] = '\0';
    }
    if (n == 0) {
        *why = "missing interface name";
        return -1;
    }
    while (is_blank(*p)) {
        p++;
    }
    while (hexval(*p) >= 0) {
        if (++idlen > 8) {
            break;
        }
        id = id * 16u + (uint32_t)hexval(*p++);
    }
    if (*p != '#') {
        *why = (idlen == 0) ? "missing frame (ID#DATA)" : "id: expected 3 or 8 hex digits and '#'";
        return -1;
    }
    if (idlen == 3) {
        if (id > GRIP_CAN_SFF_MASK) {
            *why = "id: 11-bit id above 0x7FF";
            return -1;
        }
    } else if (idlen == 8) {
        if ((id & GRIP_CAN_ID_ERR) != 0u) {
            id &= GRIP_CAN_ID_ERR | GRIP_CAN_EFF_MASK;   /* error frame: class bits kept */
        } else if (id > GRIP_CAN_EFF_MASK) {
            *why = "id: 29-bit id above 0x1FFFFFFF";
            return -1;
        } else {
            id |= GRIP_CAN_ID_EFF;
        }
    } else {
        *why = "id: expected 3 (11-bit) or 8 (29-bit) hex digits";
        return -1;
    }
    p++;   /* '#' */
    if (*p == '#') {
        int flags;
        p++;
        flags = hexval(*p);
        if (flags < 0) {
            *why = "CAN FD: expected a flags digit after ##";
            return -1;
        }
        p++;
        frame->flags = (uint8_t)(GRIP_CAN_FLAG_FD | ((flags & 1) ? GRIP_CAN_FLAG_BRS : 0u) |
                                 ((flags & 2) ? GRIP_CAN_FLAG_ESI : 0u));
        n = parse_data(&p, frame->data, 64, why);
        if (n < 0) {
            return -1;
        }
        if (!fd_len_ok(n)) {
            *why = "CAN FD: length must be 0..8, 12, 16, 20, 24, 32, 48 or 64 bytes";
            return -1;
        }
    } else if (*p == 'R' || *p == 'r') {
        p++;
        id |= GRIP_CAN_ID_RTR;
        n = 0;
        if (*p >= '0' && *p <= '8') {
            n = *p++ - '0';
        }
    } else {
        n = parse_data(&p, frame->data, 8, why);
        if (n < 0) {
            return -1;
        }
        if (*p == '_') {   /* len8_dlc suffix (DLC 9..15 of an 8-byte frame) */
            int d = hexval(p[1]);
            if (n != 8 || d < 9) {
                *why = "data: '_' DLC suffix needs 8 bytes and a digit 9..F";
                return -1;
            }
            p += 2;
        }
    }
    frame->id = id;
    frame->len = (uint8_t)n;
    while (is_blank(*p)) {
        p++;
    }
    if ((*p == 'R' || *p == 'T') && (p[1] == '\0' || is_blank(p[1]) || p[1] == '\r' || p[1] == '\n')) {
        p++;   /* direction flag of newer candump versions */
        while (is_blank(*p)) {
            p++;
        }
    }
    while (*p == '\r' || *p == '\n') {
        p++;
    }
    if (*p != '\0') {
        *why = "unexpected text after the frame";
        return -1;
    }
    return 0;
}

int candump_format(const grip_can_frame_t *frame, const char *ifname, char *buf, size_t len)
{
    char tmp[CANDUMP_LINE_MAX];
    int n;
    int i;
    int64_t t = frame->t_us;
    int64_t sec = (t >= 0) ? t / 1000000 : -((-t + 999999) / 1000000);
    int64_t us = t - sec * 1000000;

    n = snprintf(tmp, sizeof tmp, "(%010" PRId64 ".%06" PRId64 ") %s ", sec, us, ifname);
    if ((frame->id & GRIP_CAN_ID_ERR) != 0u) {
        n += snprintf(tmp + n, sizeof tmp - (size_t)n, "%08" PRIX32 "#", frame->id & (GRIP_CAN_ID_ERR | GRIP_CAN_EFF_MASK));
    } else if ((frame->id & GRIP_CAN_ID_EFF) != 0u) {
        n += snprintf(tmp + n, sizeof tmp - (size_t)n, "%08" PRIX32 "#", frame->id & GRIP_CAN_EFF_MASK);
    } else {
        n += snprintf(tmp + n, sizeof tmp - (size_t)n, "%03" PRIX32 "#", frame->id & GRIP_CAN_SFF_MASK);
    }
    if ((frame->flags & GRIP_CAN_FLAG_FD) != 0u) {
        unsigned f = ((frame->flags & GRIP_CAN_FLAG_BRS) ? 1u : 0u) | ((frame->flags & GRIP_CAN_FLAG_ESI) ? 2u : 0u);
        n += snprintf(tmp + n, sizeof tmp - (size_t)n, "#%X", f);
    } else if ((frame->id & GRIP_CAN_ID_RTR) != 0u) {
        /* candump writes the requested length after R when it is not 0 */
        n += (frame->len != 0u) ? snprintf(tmp + n, sizeof tmp - (size_t)n, "R%u", (unsigned)frame->len)
                                : snprintf(tmp + n, sizeof tmp - (size_t)n, "R");
    }
    if ((frame->id & GRIP_CAN_ID_RTR) == 0u) {
        for (i = 0; i < frame->len && i < (int)GRIP_CAN_MAX_DATA; i++) {
            n += snprintf(tmp + n, sizeof tmp - (size_t)n, "%02X", frame->data[i]);
        }
    }
    n += snprintf(tmp + n, sizeof tmp - (size_t)n, "\n");
    if ((size_t)n >= len) {
        return -1;
    }
    memcpy(buf, tmp, (size_t)n + 1u);
    return n;
}

int candump_open(candump_reader *r, const char *path, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    snprintf(r->path, sizeof r->path, "%s", path);
    if (strcmp(path, "-") == 0) {
        r->file = stdin;
        snprintf(r->path, sizeof r->path, "<stdin>");
        return 0;
    }
    r->file = fopen(path, "r");
    if (r->file == NULL) {
        snprintf(err, errlen, "cannot open log file %s: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

int candump_next(candump_reader *r, grip_can_frame_t *frame, char *ifname, char *err, size_t errlen)
{
    char name[CANDUMP_IFNAME_MAX];
    /* Each iteration consumes one line of the file. */
    for (;;) {
        const char *why = "";
        size_t n;
        const char *p;
        errno = 0;
        if (fgets(r->line, sizeof r->line, r->file) == NULL) {
            if (ferror(r->file)) {
                snprintf(err, errlen, "%s: read error after line %lu: %s", r->path, r->lineno,
                         strerror(errno ? errno : EIO));
                return -1;
            }
            return 0;
        }
        r->lineno++;
        n = strlen(r->line);
        if (n > 0 && r->line[n - 1] != '\n' && !feof(r->file)) {
            snprintf(err, errlen, "%s:%lu: line longer than %d characters", r->path, r->lineno, CANDUMP_LINE_MAX);
            return -1;
        }
        for (p = r->line; is_blank(*p); p++) {
        }
        if (*p == '\n' || *p == '\r' || *p == '\0' || *p == '#') {
            continue;   /* blank line or comment */
        }
        if (candump_parse_line(r->line, frame, name, &why) == 0) {
            if (ifname != NULL) {
                memcpy(ifname, name, sizeof name);
            }
            return 1;
        }
        if (!r->skip_bad) {
            snprintf(err, errlen, "%s:%lu: malformed candump line: %s", r->path, r->lineno, why);
            return -1;
        }
        r->skipped++;
    }
}

void candump_close(candump_reader *r)
{
    if (r->file != NULL && r->file != stdin) {
        fclose(r->file);
    }
    r->file = NULL;
}
