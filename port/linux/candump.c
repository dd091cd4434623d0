/*
 * candump.c - reading and writing `candump -l` logs (candump.h).
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
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

/* Data bytes as hex pairs, optionally separated by single '.' between
 * bytes, up to the first blank or the end. Returns the byte count, or -1
 * (odd digit count, bad digit, misplaced '.', more than max bytes). */
static int parse_data(const char **pp, uint8_t *data, int max, const char **why)
{
    const char *p = *pp;
    int n = 0;
    while (*p != '\0' && !is_blank(*p) && *p != '_' && *p != '\r' && *p != '\n') {
        int hi;
        int lo;
        if (*p == '.') {
            if (n == 0 || hexval(p[1]) < 0) {
                *why = "data: '.' only between bytes";
                return -1;
            }
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
        if ((id & GRIP_CAN_ID_ERR) != 0u && n != 8) {
            *why = "error frame: expected 8 data bytes";
            return -1;
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

static const char *byte_name(unsigned c, char *buf, size_t len)
{
    if (c == 0u) {
        return "NUL byte";
    }
    snprintf(buf, len, "byte 0x%02X", c);
    return buf;
}

/* The next line into r->line (without its '\n'), NUL-terminated; *bad is
 * the index of its first byte that is not printable ASCII, tab or CR, or
 * -1. 1 = a line, 0 = end of file, -1 = error (read error, line too long,
 * and unless skip_bad a byte that is not text: reported at once, without
 * reading the rest of the line). */
static int read_line(candump_reader *r, long *bad, char *err, size_t errlen)
{
    size_t n = 0;
    int c;
    *bad = -1;
    r->line_offset = r->offset;
    errno = 0;
    while ((c = getc(r->file)) != EOF) {
        r->offset++;
        if (c == '\n') {
            break;
        }
        if (*bad < 0 && !((c >= 0x20 && c <= 0x7E) || c == '\t' || c == '\r')) {
            *bad = (long)n;
            if (!r->skip_bad) {
                char b[16];
                r->lineno++;
                snprintf(err, errlen, "%s:%lu: malformed candump line: %s at byte offset %llu (byte %lu of the "
                         "line): not text (a candump log is ASCII)", r->path, r->lineno,
                         byte_name((unsigned)c, b, sizeof b), r->offset - 1ull, (unsigned long)n + 1ul);
                return -1;
            }
        }
        if (n >= CANDUMP_LINE_MAX) {
            snprintf(err, errlen, "%s:%lu: line longer than %d characters (at byte offset %llu)", r->path,
                     r->lineno + 1, CANDUMP_LINE_MAX, r->line_offset);
            r->lineno++;
            return -1;
        }
        r->line[n++] = (char)c;
    }
    if (c == EOF) {
        if (ferror(r->file)) {
            snprintf(err, errlen, "%s: read error after line %lu: %s", r->path, r->lineno,
                     strerror(errno ? errno : EIO));
            return -1;
        }
        if (n == 0) {
            return 0;
        }
    }
    r->line[n] = '\0';
    r->lineno++;
    return 1;
}

int candump_next(candump_reader *r, grip_can_frame_t *frame, char *ifname, char *err, size_t errlen)
{
    char name[CANDUMP_IFNAME_MAX];
    /* Each iteration consumes one line of the file. */
    for (;;) {
        const char *why = "";
        const char *p;
        long bad;
        int rc = read_line(r, &bad, err, errlen);
        if (rc <= 0) {
            return rc;
        }
        if (bad >= 0) {   /* skip_bad: read_line reports it otherwise */
            r->skipped++;
            continue;
        }
        for (p = r->line; is_blank(*p); p++) {
        }
        if (*p == '\r' || *p == '\0' || *p == '#') {
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

/* ---- frame order ------------------------------------------------------------ */

void candump_format_time(int64_t t_us, char *buf, size_t len)
{
    int64_t sec = (t_us >= 0) ? t_us / 1000000 : -((-t_us + 999999) / 1000000);
    snprintf(buf, len, "%" PRId64 ".%06" PRId64, sec, t_us - sec * 1000000);
}

int candump_order_init(candump_order *o, int64_t tolerance_us, int64_t window_us, size_t max_frames, char *err,
                       size_t errlen)
{
    memset(o, 0, sizeof *o);
    if (tolerance_us < 0 || window_us < 0 || (window_us > 0 && max_frames == 0)) {
        snprintf(err, errlen, "frame order: bad tolerance, window or frame count");
        return -1;
    }
    o->tolerance_us = tolerance_us;
    o->window_us = window_us;
    o->max_frames = max_frames;
    if (window_us > 0) {
        o->heap = malloc(max_frames * sizeof *o->heap);
        if (o->heap == NULL) {
            snprintf(err, errlen, "frame order: no memory for %lu frames", (unsigned long)max_frames);
            return -1;
        }
    }
    return 0;
}

void candump_order_free(candump_order *o)
{
    free(o->heap);
    o->heap = NULL;
    o->n = 0;
}

static int before(const candump_pending *a, const candump_pending *b)
{
    return a->frame.t_us < b->frame.t_us || (a->frame.t_us == b->frame.t_us && a->seq < b->seq);
}

static void heap_push(candump_order *o, const candump_pending *e)
{
    size_t i = o->n++;
    while (i > 0) {
        size_t up = (i - 1) / 2;
        if (!before(e, &o->heap[up])) {
            break;
        }
        o->heap[i] = o->heap[up];
        i = up;
    }
    o->heap[i] = *e;
}

static void heap_pop(candump_order *o, candump_pending *out)
{
    candump_pending last;
    size_t i = 0;
    *out = o->heap[0];
    last = o->heap[--o->n];
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= o->n) {
            break;
        }
        if (c + 1 < o->n && before(&o->heap[c + 1], &o->heap[c])) {
            c++;
        }
        if (!before(&o->heap[c], &last)) {
            break;
        }
        o->heap[i] = o->heap[c];
        i = c;
    }
    if (o->n > 0) {
        o->heap[i] = last;
    }
}

static void ms_text(int64_t us, char *buf, size_t len)
{
    snprintf(buf, len, "%" PRId64 ".%03" PRId64, us / 1000, us % 1000);
}

int candump_next_ordered(candump_reader *r, candump_order *o, grip_can_frame_t *frame, char *ifname, char *err,
                         size_t errlen)
{
    for (;;) {
        candump_pending e;
        int rc;
        if (o->window_us > 0 && o->n > 0 &&
            (o->eof || o->heap[0].frame.t_us <= o->newest_t - o->window_us)) {
            heap_pop(o, &e);
            *frame = e.frame;
            if (ifname != NULL) {
                memcpy(ifname, e.ifname, sizeof e.ifname);
            }
            return 1;
        }
        if (o->eof) {
            return 0;
        }
        rc = candump_next(r, &e.frame, e.ifname, err, errlen);
        if (rc < 0) {
            return -1;
        }
        if (rc == 0) {
            o->eof = 1;
            continue;
        }
        e.lineno = r->lineno;
        e.seq = o->seq++;
        o->frames++;
        if (o->have && e.frame.t_us < o->newest_t) {
            int64_t back = o->newest_t - e.frame.t_us;
            int64_t limit = (o->window_us > 0) ? o->window_us : o->tolerance_us;
            if (back > limit) {
                char t0[32];
                char t1[32];
                char b[32];
                char l[32];
                candump_format_time(e.frame.t_us, t0, sizeof t0);
                candump_format_time(o->newest_t, t1, sizeof t1);
                ms_text(back, b, sizeof b);
                ms_text(limit, l, sizeof l);
                if (o->window_us > 0) {
                    snprintf(err, errlen, "%s:%lu: timestamp %s goes back %s ms behind %s (line %lu): beyond the "
                             "%s ms reorder window", r->path, e.lineno, t0, b, t1, o->newest_line, l);
                } else {
                    snprintf(err, errlen, "%s:%lu: timestamp %s goes back %s ms behind %s (line %lu): more than "
                             "the %s ms a log may go back (the log is out of order: sort it, or replay it with "
                             "--reorder)", r->path, e.lineno, t0, b, t1, o->newest_line, l);
                }
                return -1;
            }
            o->out_of_order++;
            if (back > o->max_back_us) {
                o->max_back_us = back;
            }
        }
        if (!o->have || e.frame.t_us > o->newest_t) {
            o->newest_t = e.frame.t_us;
            o->newest_line = e.lineno;
            o->have = 1;
        }
        if (o->window_us == 0) {
            *frame = e.frame;
            if (ifname != NULL) {
                memcpy(ifname, e.ifname, sizeof e.ifname);
            }
            return 1;
        }
        if (o->n >= o->max_frames) {
            snprintf(err, errlen, "%s:%lu: more than %lu frames within the %" PRId64 " ms reorder window", r->path,
                     e.lineno, (unsigned long)o->max_frames, o->window_us / 1000);
            return -1;
        }
        heap_push(o, &e);
    }
}
