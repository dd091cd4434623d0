/*
 * csv.h - minimal CSV line splitting for the host tools (RFC 4180 quoting:
 * a field may be enclosed in double quotes, with "" for a literal quote, so
 * it may contain commas). One record per line: quoted fields spanning lines
 * are not supported and reported as an error.
 */
#ifndef GRIP_CSV_H
#define GRIP_CSV_H

#include <stddef.h>

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

#endif /* GRIP_CSV_H */
