/*
 * csv.c - see csv.h.
 */
#include "csv.h"

#include <errno.h>
#include <math.h>
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
