/*
 * csv.h - minimal CSV line splitting for the host tools (RFC 4180 quoting:
 * a field may be enclosed in double quotes, with "" for a literal quote, so
 * it may contain commas). One record per line: quoted fields spanning lines
 * are not supported and reported as an error.
 */
#ifndef GRIP_CSV_H
#define GRIP_CSV_H

#include <stddef.h>
#include <stdio.h>

#define CSV_MAX_FIELDS 256

typedef struct {
    char *field[CSV_MAX_FIELDS];   /* unquoted, blank-trimmed, NUL-terminated */
    int n;
} csv_record;

/* Splits `line` (no line terminator) into `rec`, using `work` (at least
 * strlen(line) + 1 bytes) as storage. Returns 0, or -1 with a reason in
 * *why (unterminated quote, text after a closing quote, too many fields). */
int csv_split(const char *line, char *work, size_t worklen, csv_record *rec, const char **why);

/* Strips a trailing "\n" or "\r\n" in place; returns the new length. */
size_t csv_chomp(char *line);

/* Parses a whole field as a finite decimal number (blanks around it
 * allowed). 0 on success. */
int csv_number(const char *field, double *v);

/* ---- bounded text line reader ---------------------------------------------
 * Reads a text file line by line into a caller-owned buffer, in O(1)
 * memory whatever the file: a line holds at most `max` bytes before its
 * '\n' (a longer one is an error, reported without reading on). Every byte
 * must be text: printable ASCII, tab, a CR directly before the '\n' (or the
 * end), and, in UTF-8 mode, well-formed UTF-8 (no overlong forms,
 * surrogates or code points above U+10FFFF); NUL, other control bytes, DEL
 * and, in ASCII mode, every byte >= 0x80 are errors. Errors name the file,
 * the line and the byte offset in the file (counted from 0). A UTF-8 byte
 * order mark at the start of the file is skipped. */
typedef struct {
    FILE *file;
    const char *path;                 /* for messages ("<stdin>" for "-") */
    int utf8;                         /* 1: UTF-8 text; 0: ASCII only */
    size_t max;                       /* longest line, bytes */
    char *line;                       /* the current line, NUL-terminated, no CR/LF */
    size_t len;                       /* its length */
    unsigned long lineno;             /* its number, from 1 */
    unsigned long long offset;        /* bytes read so far */
    unsigned long long line_offset;   /* file offset of its first byte */
    int error;                        /* after -1: CSV_ERR_* */
    int partial;                      /* after -1: the line was not read to its end */
} csv_reader;

/* csv_reader.error after csv_read_line returned -1. */
#define CSV_ERR_READ 1    /* the file could not be read */
#define CSV_ERR_TEXT 2    /* a byte that is not text (NUL, control, not UTF-8) */
#define CSV_ERR_LONG 3    /* a line longer than max */

/* Opens path ("-" = standard input). buf holds at least max + 1 bytes and
 * stays the caller's. 0, or -1 with "cannot open PATH: reason" in err. */
int csv_reader_open(csv_reader *r, const char *path, char *buf, size_t max, int utf8, char *err, size_t errlen);

/* 1: the next line is in r->line / r->len; 0: end of file; -1: error, the
 * message ("PATH:LINE: ...") in err. */
int csv_read_line(csv_reader *r, char *err, size_t errlen);

/* After a CSV_ERR_TEXT line that was not read to its end (r->partial):
 * reads on to its '\n' (or the end), so the next csv_read_line starts on
 * the next line. 0, or -1 (err: "line longer than") if the line holds more
 * than r->max bytes in all: an endless line (/dev/zero) is not read on. */
int csv_skip_line(csv_reader *r, char *err, size_t errlen);

void csv_reader_close(csv_reader *r);

/* Index of the name in known[0..n) nearest to name (edit distance with
 * transpositions, letter case ignored), with the distance in *dist; -1 if
 * n is 0. Names longer than 63 bytes are compared by their first 63. */
int csv_nearest(const char *name, const char *const *known, int n, int *dist);

#endif /* GRIP_CSV_H */
