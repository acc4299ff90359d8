/*
 * _csv_scan.h - one pass over the body of a numeric CSV table (the lines
 * after the header): the wanted numeric cells as float64, each wanted text
 * cell as an index into the distinct cells of its column, or "not plain".
 *
 * A plain body is what every reader path reads the same way: ASCII only,
 * no quote character, no control character but tab and newline ('\n'; the
 * readers turn "\r\n" and "\r" into '\n' first), every non-blank line with
 * the same number of cells (cells split at every comma), at least as many
 * as the highest wanted position needs. A blank line (spaces and tabs only)
 * is skipped. A numeric cell, stripped of spaces and tabs, is
 *   - one of the "missing" words, any case (e.g. "", "nan", "NA", "-"): NaN;
 *   - [+-] digits [. digits] or [+-] . digits, then optionally e|E [+-] digits:
 *     the value Python's float() gives, correctly rounded (below);
 *   - [+-] inf or infinity, any case: +-infinity (as float()).
 * Anything else (a signed "nan", "1_000", hexadecimal, a stray character)
 * is not plain: the scan stops and says where (body line and cell), and
 * the caller hands the text to the readers' other paths, which decide the
 * value or the error. So the scan never decides an error.
 *
 * Correct rounding: a decimal with at most 15 significant digits and a
 * power of ten up to 22 is one exact integer times or divided by one exact
 * power of ten, a single IEEE operation, so correctly rounded (Clinger's
 * fast path; needs double arithmetic in double, FLT_EVAL_METHOD 0, as
 * SSE2 and AArch64 have). Every other number goes to the caller's
 * conversion (toDouble; the extension gives Python's own,
 * PyOS_string_to_double, so the value is float()'s on every platform), or
 * to the C library's strtod without one (correctly rounded in glibc, musl
 * and macOS), whose end must be the cell's end (else, e.g. under another
 * LC_NUMERIC, the body is not plain).
 *
 * Not part of the microcontroller core: C99 and C++, bounds-checked, no
 * allocation (the caller gives every array).
 */
#ifndef FUSION_ALTITUDE_CSV_SCAN_H
#define FUSION_ALTITUDE_CSV_SCAN_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Longest numeric cell handed to strtod (characters); a longer one is not plain. */
#define CSV_SCAN_MAX_NUMBER 400
/* Most numeric and text columns one scan reads. */
#define CSV_SCAN_MAX_COLUMNS 64

typedef enum {
    CsvScanOk = 0,
    /* A byte outside printable ASCII, tab and newline, or a quote character. */
    CsvScanNotPlainText = 1,
    /* A line with another number of cells than the first, or too few for a wanted column. */
    CsvScanRagged = 2,
    /* A numeric cell that is not a plain number nor a missing word. */
    CsvScanNotNumber = 3,
    /* More rows than the output arrays hold, or bad arguments. */
    CsvScanFull = 4,
} CsvScanStatus;

/* A decimal string to double, as strtod: the value, *end after the last character converted. */
typedef double (*CsvScanToDouble)(const char *text, char **end);

typedef struct {
    const char *body;        /* the body's bytes (need not end with NUL) */
    size_t size;             /* bytes */
    const int *numeric;      /* cell position of each numeric column, in output order */
    size_t numericCount;
    const int *text;         /* cell position of each text column */
    size_t textCount;
    const char *missing;     /* the missing words, lower case, each followed by '\n' (e.g. "\nnan\nna\n-\n") */
    size_t missingSize;
    size_t capacity;         /* rows the output arrays hold */
    double *numbers;         /* out: numericCount x capacity, column-major (row r of column k at k x capacity + r) */
    int64_t *textIndex;      /* out: capacity x textCount, row-major: each cell's index among its column's distinct ones */
    int64_t *distinctStart;  /* out: textCount x capacity: byte offset of each distinct (stripped) text cell */
    int64_t *distinctLength; /* out: textCount x capacity: its length */
    int64_t *hashSlots;      /* work: textCount x hashSize, any content */
    size_t hashSize;         /* a power of two, at least 2 x capacity (ignored without text columns) */
    CsvScanToDouble toDouble; /* the conversion of the numbers off Clinger's fast path; NULL: strtod */
} CsvScanArguments;

typedef struct {
    size_t rows;                                  /* rows written */
    size_t distinct[CSV_SCAN_MAX_COLUMNS];        /* distinct cells of each text column */
    size_t line;                                  /* body line (0-based) where a scan that is not Ok stopped */
    size_t cell;                                  /* cell position there */
} CsvScanResult;

static inline int CsvScanIsSpace(const char c) { return c == ' ' || c == '\t'; }

static inline int CsvScanIsDigit(const char c) { return c >= '0' && c <= '9'; }

/* s[0..n) equals the lower-case word w[0..n) in any case (ASCII). */
static inline int CsvScanSameWord(const char *s, const char *w, const size_t n) {
    size_t i;
    for (i = 0; i < n; i++) {
        const char c = (s[i] >= 'A' && s[i] <= 'Z') ? (char)(s[i] - 'A' + 'a') : s[i];
        if (c != w[i]) {
            return 0;
        }
    }
    return 1;
}

/* The stripped cell s[0..n) is one of the '\n'-terminated missing words (any case). */
static inline int CsvScanIsMissing(const char *s, const size_t n, const char *missing, const size_t missingSize) {
    size_t start = 0;
    size_t i;
    for (i = 0; i < missingSize; i++) {
        if (missing[i] == '\n') {
            if (i - start == n && CsvScanSameWord(s, missing + start, n)) {
                return 1;
            }
            start = i + 1;
        }
    }
    return 0;
}

/* Exact powers of ten as doubles: 10^0 .. 10^22 (10^22 < 2^53 x 2^22, every one exact). */
static const double csvScanPowers[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                         1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/*
 * The stripped numeric cell s[0..n) as a double, by the grammar of the file
 * comment. Returns 1 and sets *value, or 0 when it is not plain.
 */
static inline int CsvScanNumber(const char *s, const size_t n, double *const value, const CsvScanToDouble toDouble) {
    size_t i = 0;
    int negative = 0;
    uint64_t mantissa = 0;
    int digits = 0;       /* significant digits taken into the mantissa */
    int dropped = 0;      /* significant digits beyond 19 (not in the mantissa) */
    long exponent = 0;    /* power of ten of the mantissa's last digit */
    int any = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) {
        negative = s[i] == '-';
        i++;
    }
    if (n - i == 3 || n - i == 8) {
        if ((n - i == 3 && CsvScanSameWord(s + i, "inf", 3)) || (n - i == 8 && CsvScanSameWord(s + i, "infinity", 8))) {
            *value = negative ? -HUGE_VAL : HUGE_VAL;
            return 1;
        }
    }
    for (; i < n && CsvScanIsDigit(s[i]); i++) {
        any = 1;
        if (digits == 0 && s[i] == '0') {
            continue; /* leading zero */
        }
        if (digits < 19) {
            mantissa = mantissa * 10u + (uint64_t)(s[i] - '0');
            digits++;
        } else {
            dropped++;
        }
    }
    exponent = dropped;
    if (i < n && s[i] == '.') {
        i++;
        for (; i < n && CsvScanIsDigit(s[i]); i++) {
            any = 1;
            if (digits == 0 && s[i] == '0') {
                exponent--; /* leading zero after the point */
                continue;
            }
            if (digits < 19) {
                mantissa = mantissa * 10u + (uint64_t)(s[i] - '0');
                digits++;
                exponent--;
            } else {
                dropped++;
            }
        }
    }
    if (!any) {
        return 0;
    }
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        int exponentNegative = 0;
        long written = 0;
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) {
            exponentNegative = s[i] == '-';
            i++;
        }
        if (i >= n || !CsvScanIsDigit(s[i])) {
            return 0;
        }
        for (; i < n && CsvScanIsDigit(s[i]); i++) {
            if (written < 100000) {
                written = written * 10 + (s[i] - '0');
            }
        }
        exponent += exponentNegative ? -written : written;
    }
    if (i != n) {
        return 0;
    }
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0
    if (mantissa == 0 && dropped == 0) {
        *value = negative ? -0.0 : 0.0;
        return 1;
    }
    if (digits <= 15 && dropped == 0 && exponent >= -22 && exponent <= 22) {
        /* Clinger: both operands exact, one correctly rounded operation */
        const double exact = (double)mantissa;
        const double scaled = exponent < 0 ? exact / csvScanPowers[-exponent] : exact * csvScanPowers[exponent];
        *value = negative ? -scaled : scaled;
        return 1;
    }
#endif
    {
        char copy[CSV_SCAN_MAX_NUMBER + 1];
        char *end = NULL;
        if (n > CSV_SCAN_MAX_NUMBER) {
            return 0;
        }
        memcpy(copy, s, n);
        copy[n] = '\0';
        *value = toDouble != NULL ? toDouble(copy, &end) : strtod(copy, &end);
        return end == copy + n;
    }
}

/* Newlines ('\n') in s[0..n): eight bytes at a time (a byte equal to '\n' is a zero byte of the word XOR
   0x0a0a...; each zero byte leaves its top bit in ~t, and the multiply sums the eight bits). */
static inline size_t CsvScanNewlines(const char *const s, const size_t n) {
    const uint64_t low7 = 0x7f7f7f7f7f7f7f7fu;
    size_t count = 0;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t word;
        uint64_t t;
        memcpy(&word, s + i, 8);
        word ^= 0x0a0a0a0a0a0a0a0au;
        t = ((word & low7) + low7) | word;
        count += (size_t)((((~t) >> 7) & 0x0101010101010101u) * 0x0101010101010101u >> 56);
    }
    for (; i < n; i++) {
        count += s[i] == '\n';
    }
    return count;
}

/* The longest run of digits in s[0..n), the decimal points left out ("12.345" is one run of 5): a sample of a body
   with no run longer than 15 holds only numbers of Clinger's fast path. */
static inline size_t CsvScanLongestDigitRun(const char *const s, const size_t n) {
    size_t longest = 0;
    size_t run = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        if (CsvScanIsDigit(s[i])) {
            run++;
            longest = run > longest ? run : longest;
        } else if (s[i] != '.') {
            run = 0;
        }
    }
    return longest;
}

/* FNV-1a of s[0..n). */
static inline uint64_t CsvScanHash(const char *s, const size_t n) {
    uint64_t hash = 1469598103934665603u;
    size_t i;
    for (i = 0; i < n; i++) {
        hash = (hash ^ (uint8_t)s[i]) * 1099511628211u;
    }
    return hash;
}

/* The index of the text cell s[0..n) among column k's distinct cells, adding it if new; *previous: the row
   before's (-1 at first), tried first (a logger's text columns mostly repeat it). */
static inline int64_t CsvScanDistinct(const CsvScanArguments *const a, CsvScanResult *const result, const size_t k,
                                      const char *s, const size_t n, int64_t *const previous) {
    int64_t *const slots = a->hashSlots + k * a->hashSize;
    int64_t *const starts = a->distinctStart + k * a->capacity;
    int64_t *const lengths = a->distinctLength + k * a->capacity;
    size_t slot;
    if (*previous >= 0 && (size_t)lengths[*previous] == n && memcmp(a->body + starts[*previous], s, n) == 0) {
        return *previous;
    }
    slot = (size_t)CsvScanHash(s, n) & (a->hashSize - 1);
    for (;;) {
        const int64_t found = slots[slot];
        if (found < 0) {
            const int64_t index = (int64_t)result->distinct[k]++;
            slots[slot] = index;
            starts[index] = (int64_t)(s - a->body);
            lengths[index] = (int64_t)n;
            *previous = index;
            return index;
        }
        if ((size_t)lengths[found] == n && memcmp(a->body + starts[found], s, n) == 0) {
            *previous = found;
            return found;
        }
        slot = (slot + 1) & (a->hashSize - 1);
    }
}

/* A byte a plain body may hold in a cell: printable ASCII but the quote character, or a tab. */
static inline int CsvScanIsPlain(const char c) {
    return (c >= 0x20 && c < 0x7f && c != '"') || c == '\t';
}

/* The class of every byte for the walk over a cell (CsvScanCell): 0 a plain cell byte (CsvScanIsPlain), 1 a cell's
   end (',' or '\n'), 2 neither (not plain). One load and one test a byte instead of six comparisons. */
static const unsigned char csvScanByteClass[256] = {
    2, 2, 2, 2, 2, 2, 2, 2, 2, 0, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, /* 0x00 */
    0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, /* 0x20 */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, /* 0x40 */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, /* 0x60 */
    2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, /* 0x80 */
    2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, /* 0xa0 */
    2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, /* 0xc0 */
    2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, /* 0xe0 */
};

/*
 * The common numeric cell at s, read in one pass: [spaces] [-+] digits [. digits] [e|E [-+] digits] [spaces],
 * at most 15 significant digits and a power of ten within 22 (Clinger's fast path). Returns the end of the cell
 * (its comma, newline or the body's end) and sets *value, or NULL when the cell is not of this form (the
 * general reading, CsvScanCell, decides it).
 */
static inline const char *CsvScanSimpleNumber(const char *s, const char *const end, double *const value) {
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0
    int negative = 0;
    uint64_t mantissa = 0;
    int digits = 0;
    int any = 0;
    long exponent = 0;
    while (s < end && CsvScanIsSpace(*s)) {
        s++;
    }
    if (s < end && (*s == '-' || *s == '+')) {
        negative = *s == '-';
        s++;
    }
    /* every digit, leading zeros too, goes into the mantissa: more than 15 leave this path (the general one reads
       them), so it never overflows where it is used */
    for (; s < end && CsvScanIsDigit(*s); s++) {
        mantissa = mantissa * 10u + (uint64_t)(*s - '0');
        digits++;
    }
    if (s < end && *s == '.') {
        const char *const point = s;
        for (s++; s < end && CsvScanIsDigit(*s); s++) {
            mantissa = mantissa * 10u + (uint64_t)(*s - '0');
        }
        digits += (int)(s - point - 1);
        exponent = -(long)(s - point - 1);
    }
    any = digits > 0;
    if (!any || digits > 15) {
        return NULL;
    }
    if (s < end && (*s == 'e' || *s == 'E')) {
        int exponentNegative = 0;
        long written = 0;
        s++;
        if (s < end && (*s == '-' || *s == '+')) {
            exponentNegative = *s == '-';
            s++;
        }
        if (s >= end || !CsvScanIsDigit(*s)) {
            return NULL;
        }
        for (; s < end && CsvScanIsDigit(*s); s++) {
            if (written < 1000) {
                written = written * 10 + (*s - '0');
            }
        }
        exponent += exponentNegative ? -written : written;
    }
    while (s < end && CsvScanIsSpace(*s)) {
        s++;
    }
    if ((s < end && *s != ',' && *s != '\n') || exponent < -22 || exponent > 22) {
        return NULL;
    }
    {
        const double exact = (double)mantissa; /* below 10^15: exact */
        const double scaled = exponent < 0 ? exact / csvScanPowers[-exponent] : exact * csvScanPowers[exponent];
        *value = negative ? -scaled : scaled;
    }
    return s;
#else
    (void)s;
    (void)end;
    (void)value;
    return NULL;
#endif
}

/*
 * Any cell at s: its end (comma, newline or the body's end) in *next, its characters checked plain (else
 * CsvScanNotPlainText). A numeric cell (role > 0) is read into *number (NaN for a missing word; else
 * CsvScanNotNumber); a text cell's stripped bounds go to *first, *last.
 */
static inline CsvScanStatus CsvScanCell(const CsvScanArguments *const a, const char *s, const char *const end,
                                        const signed char role, double *const number, const char **const first,
                                        const char **const last, const char **const next) {
    const char *stop = s;
    while (stop < end && csvScanByteClass[(unsigned char)*stop] == 0) {
        stop++;
    }
    if (stop < end && csvScanByteClass[(unsigned char)*stop] == 2) {
        return CsvScanNotPlainText;
    }
    *next = stop;
    while (s < stop && CsvScanIsSpace(*s)) {
        s++;
    }
    while (stop > s && CsvScanIsSpace(stop[-1])) {
        stop--;
    }
    *first = s;
    *last = stop;
    if (role > 0 && !CsvScanNumber(s, (size_t)(stop - s), number, a->toDouble)) {
        if (!CsvScanIsMissing(s, (size_t)(stop - s), a->missing, a->missingSize)) {
            return CsvScanNotNumber;
        }
        *number = (double)NAN; /* a quiet NaN, as numpy's np.nan */
    }
    return CsvScanOk;
}

/* The end of a blank line (spaces and tabs only) starting at s, or NULL if the line is not blank. */
static inline const char *CsvScanBlank(const char *s, const char *const end) {
    while (s < end && CsvScanIsSpace(*s)) {
        s++;
    }
    return (s >= end || *s == '\n') ? s : NULL;
}

/*
 * Scan the body once. Returns the status; result->rows rows are written
 * (result->line and ->cell say where a scan that is not Ok stopped).
 */
static inline CsvScanStatus CsvScan(const CsvScanArguments *const a, CsvScanResult *const result) {
    signed char role[CSV_SCAN_MAX_COLUMNS * 4]; /* per cell position: +1 numeric, -1 text, 0 skipped */
    int slot[CSV_SCAN_MAX_COLUMNS * 4];         /* its output column */
    int64_t previous[CSV_SCAN_MAX_COLUMNS];     /* per text column: the row before's distinct cell */
    size_t width = 0;                           /* cells of the first non-blank line */
    size_t needed = 0;                          /* cells the wanted positions need */
    size_t i;
    const char *s = a->body;
    const char *const end = a->body + a->size;
    memset(result, 0, sizeof(*result));
    memset(role, 0, sizeof(role));
    if (a->numericCount + a->textCount > CSV_SCAN_MAX_COLUMNS ||
        (a->textCount > 0 && (a->hashSize < 2 * a->capacity || (a->hashSize & (a->hashSize - 1)) != 0))) {
        return CsvScanFull;
    }
    for (i = 0; i < a->numericCount + a->textCount; i++) {
        const int position = i < a->numericCount ? a->numeric[i] : a->text[i - a->numericCount];
        if (position < 0 || position >= CSV_SCAN_MAX_COLUMNS * 4 || role[position] != 0) {
            return CsvScanFull; /* out of range, or a position asked twice: not for this scanner */
        }
        role[position] = (signed char)(i < a->numericCount ? 1 : -1);
        slot[position] = (int)(i < a->numericCount ? i : i - a->numericCount);
        needed = (size_t)position + 1 > needed ? (size_t)position + 1 : needed;
    }
    for (i = 0; i < a->textCount * a->hashSize; i++) {
        a->hashSlots[i] = -1;
    }
    for (i = 0; i < CSV_SCAN_MAX_COLUMNS; i++) {
        previous[i] = -1;
    }
    while (s < end) {
        const char *const blank = CsvScanBlank(s, end);
        const size_t row = result->rows;
        size_t position = 0;
        if (blank != NULL) {
            s = blank < end ? blank + 1 : end;
            result->line++;
            continue;
        }
        if (row >= a->capacity) {
            return CsvScanFull;
        }
        for (;;) {
            const signed char kind = position < CSV_SCAN_MAX_COLUMNS * 4 ? role[position] : 0;
            const char *next = NULL;
            if (kind > 0) {
                next = CsvScanSimpleNumber(s, end, a->numbers + (size_t)slot[position] * a->capacity + row);
            }
            if (next == NULL) {
                const char *first = NULL;
                const char *last = NULL;
                double *const number = kind > 0 ? a->numbers + (size_t)slot[position] * a->capacity + row : NULL;
                const CsvScanStatus status = CsvScanCell(a, s, end, kind, number, &first, &last, &next);
                if (status != CsvScanOk) {
                    result->cell = position;
                    return status;
                }
                if (kind < 0) {
                    const size_t k = (size_t)slot[position];
                    a->textIndex[row * a->textCount + k] =
                        CsvScanDistinct(a, result, k, first, (size_t)(last - first), &previous[k]);
                }
            }
            position++;
            s = next < end ? next + 1 : end;
            if (next >= end || *next == '\n') {
                break;
            }
        }
        if (width == 0) {
            width = position;
        }
        if (position != width || position < needed) {
            result->cell = position;
            return CsvScanRagged;
        }
        result->rows++;
        result->line++;
    }
    return CsvScanOk;
}

#endif
