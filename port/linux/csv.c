/*
 * csv.c - see csv.h.
 */
#include "csv.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *trim(char *s)
{
    char *end;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    end = s + strlen(s);
    while (end > s && (end[-1] == ' ' || end[-1] == '\t')) {
        *--end = '\0';
    }
    return s;
}

int csv_split(const char *line, char *work, size_t worklen, csv_record *rec, const char **why)
{
    const char *p = line;
    char *w = work;
    size_t need = strlen(line) + 1;
    rec->n = 0;
    if (worklen < need) {
        *why = "line too long";
        return -1;
    }
    for (;;) {
        char *start = w;
        const char *q = p;
        /* blanks before an opening quote are allowed */
        while (*q == ' ' || *q == '\t') {
            q++;
        }
        if (rec->n >= CSV_MAX_FIELDS) {
            *why = "too many fields";
            return -1;
        }
        if (*q == '"') {
            p = q + 1;
            for (;;) {
                if (*p == '\0') {
                    *why = "unterminated quoted field";
                    return -1;
                }
                if (*p == '"') {
                    if (p[1] == '"') {
                        *w++ = '"';
                        p += 2;
                        continue;
                    }
                    p++;
                    break;
                }
                *w++ = *p++;
            }
            while (*p == ' ' || *p == '\t') {
                p++;
            }
            if (*p != ',' && *p != '\0') {
                *why = "text after a closing quote";
                return -1;
            }
            *w++ = '\0';
            rec->field[rec->n++] = start;   /* quoted content kept as is */
        } else {
            while (*p != ',' && *p != '\0') {
                if (*p == '"') {
                    *why = "quote inside an unquoted field";
                    return -1;
                }
                *w++ = *p++;
            }
            *w++ = '\0';
            rec->field[rec->n++] = trim(start);
        }
        if (*p == ',') {
            p++;
            continue;
        }
        break;
    }
    return 0;
}

size_t csv_chomp(char *line)
{
    size_t n = strlen(line);
    if (n > 0 && line[n - 1] == '\n') {
        line[--n] = '\0';
    }
    if (n > 0 && line[n - 1] == '\r') {
        line[--n] = '\0';
    }
    return n;
}

int csv_number(const char *field, double *v)
{
    char *end = NULL;
    const char *p = field;
    while (*p == ' ' || *p == '\t') {
        p++;
    }
    if (*p == '\0') {
        return -1;
    }
    /* decimal only: no hex, inf or nan */
    {
        const char *c;
        for (c = p; *c != '\0'; c++) {
            if (!((*c >= '0' && *c <= '9') || *c == '+' || *c == '-' || *c == '.' || *c == 'e' ||
                  *c == 'E' || *c == ' ' || *c == '\t')) {
                return -1;
            }
        }
    }
    errno = 0;
    *v = strtod(p, &end);
    if (end == p || errno == ERANGE || !isfinite(*v)) {
        return -1;
    }
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    return (*end == '\0') ? 0 : -1;
}

/* ---- bounded text line reader -------------------------------------------- */

int csv_reader_open(csv_reader *r, const char *path, char *buf, size_t max, int utf8, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    r->line = buf;
    r->max = max;
    r->utf8 = utf8;
    r->line[0] = '\0';
    if (strcmp(path, "-") == 0) {
        r->file = stdin;
        r->path = "<stdin>";
        return 0;
    }
    r->path = path;
    r->file = fopen(path, "r");
    if (r->file == NULL) {
        snprintf(err, errlen, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

void csv_reader_close(csv_reader *r)
{
    if (r->file != NULL && r->file != stdin) {
        fclose(r->file);
    }
    r->file = NULL;
}

/* Length of the well-formed UTF-8 sequence at s (n bytes available), or 0. */
static size_t utf8_seq(const unsigned char *s, size_t n)
{
    unsigned c = s[0];
    size_t len;
    unsigned lo = 0x80u;
    unsigned hi = 0xBFu;
    size_t i;
    if (c >= 0xC2u && c <= 0xDFu) {
        len = 2;
    } else if (c >= 0xE0u && c <= 0xEFu) {
        len = 3;
        if (c == 0xE0u) {
            lo = 0xA0u;   /* no overlong forms */
        } else if (c == 0xEDu) {
            hi = 0x9Fu;   /* no surrogates */
        }
    } else if (c >= 0xF0u && c <= 0xF4u) {
        len = 4;
        if (c == 0xF0u) {
            lo = 0x90u;
        } else if (c == 0xF4u) {
            hi = 0x8Fu;   /* <= U+10FFFF */
        }
    } else {
        return 0;
    }
    if (n < len || s[1] < lo || s[1] > hi) {
        return 0;
    }
    for (i = 2; i < len; i++) {
        if (s[i] < 0x80u || s[i] > 0xBFu) {
            return 0;
        }
    }
    return len;
}

/* Length of the text character at s (n bytes available, the line's last
 * byte at s[n - 1]), or 0 if s[0] does not start one. */
static size_t text_char(const csv_reader *r, const unsigned char *s, size_t n)
{
    unsigned char b = s[0];
    if ((b >= 0x20u && b < 0x7Fu) || b == '\t' || (b == '\r' && n == 1)) {
        return 1;
    }
    if (b >= 0x80u && r->utf8) {
        return utf8_seq(s, n);
    }
    return 0;
}

int csv_read_line(csv_reader *r, char *err, size_t errlen)
{
    size_t n = 0;
    size_t i;
    int c;
    int too_long = 0;
    r->line_offset = r->offset;
    r->error = 0;
    r->partial = 0;
    errno = 0;
    while ((c = getc_unlocked(r->file)) != EOF) {
        r->offset++;
        if (c == '\n') {
            break;
        }
        if (n >= r->max) {
            too_long = 1;
            r->partial = 1;
            break;
        }
        r->line[n++] = (char)c;
        if (c == 0 || (c < 0x20 && c != '\t' && c != '\r') || c == 0x7F) {
            r->partial = 1;
            break;   /* not text in any encoding: report it without reading on */
        }
    }
    if (c == EOF && ferror(r->file)) {
        r->error = CSV_ERR_READ;
        snprintf(err, errlen, "%s: read error after line %lu: %s", r->path, r->lineno, strerror(errno ? errno : EIO));
        return -1;
    }
    if (c == EOF && n == 0) {
        return 0;
    }
    r->lineno++;
    i = 0;
    if (r->utf8 && r->lineno == 1 && n >= 3 && memcmp(r->line, "\xEF\xBB\xBF", 3) == 0) {
        i = 3;   /* byte order mark */
    }
    while (i < (too_long && n > 3 ? n - 3 : n)) {   /* a cut line may end in part of a character */
        size_t k = text_char(r, (const unsigned char *)r->line + i, n - i);
        unsigned char b = (unsigned char)r->line[i];
        char text[48];
        if (k > 0) {
            i += k;
            continue;
        }
        if (b == 0u) {
            snprintf(text, sizeof text, "NUL byte");
        } else if (b >= 0x80u && r->utf8) {
            snprintf(text, sizeof text, "byte 0x%02X that is not valid UTF-8", (unsigned)b);
        } else if (b >= 0x80u) {
            snprintf(text, sizeof text, "byte 0x%02X (not ASCII)", (unsigned)b);
        } else {
            snprintf(text, sizeof text, "control byte 0x%02X", (unsigned)b);
        }
        snprintf(err, errlen, "%s:%lu: %s at byte offset %llu (byte %lu of the line): not text", r->path, r->lineno,
                 text, r->line_offset + (unsigned long long)i, (unsigned long)i + 1ul);
        r->error = CSV_ERR_TEXT;
        return -1;
    }
    if (too_long) {
        r->error = CSV_ERR_LONG;
        snprintf(err, errlen, "%s:%lu: line longer than %lu bytes (line starts at byte offset %llu)", r->path,
                 r->lineno, (unsigned long)r->max, r->line_offset);
        return -1;
    }
    r->line[n] = '\0';
    if (n > 0 && r->line[n - 1] == '\r') {
        r->line[--n] = '\0';
    }
    if (r->utf8 && r->lineno == 1 && n >= 3 && memcmp(r->line, "\xEF\xBB\xBF", 3) == 0) {
        memmove(r->line, r->line + 3, n - 2);
        n -= 3;
    }
    r->len = n;
    return 1;
}

int csv_skip_line(csv_reader *r, char *err, size_t errlen)
{
    unsigned long long n = r->offset - r->line_offset;   /* bytes of the line read so far */
    int c;
    if (!r->partial) {
        return 0;
    }
    r->partial = 0;
    while ((c = getc_unlocked(r->file)) != EOF) {
        r->offset++;
        if (c == '\n') {
            return 0;
        }
        if (++n > r->max) {
            snprintf(err, errlen, "%s:%lu: line longer than %lu bytes (line starts at byte offset %llu)", r->path,
                     r->lineno, (unsigned long)r->max, r->line_offset);
            r->error = CSV_ERR_LONG;
            return -1;
        }
    }
    if (ferror(r->file)) {
        snprintf(err, errlen, "%s: read error after line %lu: %s", r->path, r->lineno, strerror(errno ? errno : EIO));
        r->error = CSV_ERR_READ;
        return -1;
    }
    return 0;
}

/* ---- nearest name ------------------------------------------------------------ */

static int lower(int c)
{
    return (c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c;
}

/* Optimal string alignment distance (edits and adjacent transpositions),
 * letter case ignored; both strings at most 63 bytes. */
static int distance(const char *a, const char *b)
{
    int d[64][64];
    int la = (int)strlen(a);
    int lb = (int)strlen(b);
    int i;
    int j;
    la = la > 63 ? 63 : la;
    lb = lb > 63 ? 63 : lb;
    for (i = 0; i <= la; i++) {
        d[i][0] = i;
    }
    for (j = 0; j <= lb; j++) {
        d[0][j] = j;
    }
    for (i = 1; i <= la; i++) {
        for (j = 1; j <= lb; j++) {
            int cost = lower((unsigned char)a[i - 1]) != lower((unsigned char)b[j - 1]);
            int v = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < v) {
                v = d[i][j - 1] + 1;
            }
            if (d[i - 1][j - 1] + cost < v) {
                v = d[i - 1][j - 1] + cost;
            }
            if (i > 1 && j > 1 && lower((unsigned char)a[i - 1]) == lower((unsigned char)b[j - 2]) &&
                lower((unsigned char)a[i - 2]) == lower((unsigned char)b[j - 1]) && d[i - 2][j - 2] + 1 < v) {
                v = d[i - 2][j - 2] + 1;
            }
            d[i][j] = v;
        }
    }
    return d[la][lb];
}

int csv_nearest(const char *name, const char *const *known, int n, int *dist)
{
    int best = -1;
    int bd = 0;
    int k;
    for (k = 0; k < n; k++) {
        int dk = distance(name, known[k]);
        if (best < 0 || dk < bd) {
            best = k;
            bd = dk;
        }
    }
    if (dist != NULL) {
        *dist = bd;
    }
    return best;
}
