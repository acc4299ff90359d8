/**
 * @file fuzz_csv.c
 * @brief libFuzzer target for the C scan of numeric CSV bodies of the log readers
 * (fusion_altitude/logs/_csv_scan.h), built with clang under AddressSanitizer +
 * UndefinedBehaviorSanitizer:
 *
 *   clang -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
 *       -Ifusion_altitude/logs -Icsrc csrc/fuzz/fuzz_csv.c -o fuzz_csv
 *   ./fuzz_csv -max_total_time=600 csrc/fuzz/corpus_csv
 *
 * The input: one byte choosing which of the first four cell positions are
 * numeric, text or skipped, then the body. Asserted on every input (abort, so
 * libFuzzer reports a crash), against a plain transcription of the rules of
 * _csv_scan.h's comment (ReferenceCell below: split at commas, strip spaces
 * and tabs, a missing word or strtod of the whole cell):
 *   - a scan that is Ok read every non-blank line as a row, each numeric cell
 *     bit for bit strtod's value of the stripped cell (so Clinger's fast path
 *     never differs from the C library) or NaN for a missing word, each text
 *     cell the stripped cell it names;
 *   - a scan that is not Ok stopped on a line of the body, and the reference
 *     finds that line not plain (or a wanted cell there not a number).
 * No read or write outside the input (ASan), no undefined behaviour (UBSan).
 */
#include "_csv_scan.h"
#include "fuzz_common.h" /* CHECK */

#define FUZZ_CSV_MISSING "\nnan\nna\nn/a\nnull\nnone\n-\n"

/* The k-th line of body (0-based): its start and end (exclusive); 0 if there is no such line. */
static int NthLine(const char *body, size_t size, size_t k, size_t *start, size_t *stop) {
    size_t i = 0;
    size_t line = 0;
    while (i <= size) {
        size_t j = i;
        while (j < size && body[j] != '\n') {
            j++;
        }
        if (line == k) {
            *start = i;
            *stop = j;
            return i < size; /* a line starts before the end (the scan's lines) */
        }
        line++;
        i = j + 1;
    }
    return 0;
}

/* Cell `position` of the line [start, stop): its stripped bounds; 0 if the line has fewer cells. */
static int Cell(const char *body, size_t start, size_t stop, size_t position, size_t *first, size_t *last) {
    size_t cell = 0;
    size_t i = start;
    for (;;) {
        size_t j = i;
        while (j < stop && body[j] != ',') {
            j++;
        }
        if (cell == position) {
            while (i < j && (body[i] == ' ' || body[i] == '\t')) {
                i++;
            }
            while (j > i && (body[j - 1] == ' ' || body[j - 1] == '\t')) {
                j--;
            }
            *first = i;
            *last = j;
            return 1;
        }
        if (j >= stop) {
            return 0;
        }
        cell++;
        i = j + 1;
    }
}

/* The reference reading of a numeric cell: 1 and its value, or 0 if it is neither a number nor a missing word. */
static int ReferenceCell(const char *cell, size_t n, double *value) {
    char copy[CSV_SCAN_MAX_NUMBER + 1];
    char *end = NULL;
    size_t i;
    if (CsvScanIsMissing(cell, n, FUZZ_CSV_MISSING, sizeof(FUZZ_CSV_MISSING) - 1)) {
        *value = (double)NAN;
        return 1;
    }
    if (n == 0 || n > CSV_SCAN_MAX_NUMBER) {
        return 0;
    }
    for (i = 0; i < n; i++) { /* the grammar strtod shares with Python's float: no hex, no nan(...), no spaces */
        const char c = cell[i];
        if (!(CsvScanIsDigit(c) || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-' || (c | 32) == 'i' ||
              (c | 32) == 'n' || (c | 32) == 'f' || (c | 32) == 't' || (c | 32) == 'y')) {
            return 0;
        }
    }
    memcpy(copy, cell, n);
    copy[n] = '\0';
    *value = strtod(copy, &end);
    return end == copy + n; /* decimals, inf and infinity, as Python's float */
}

/* A scan that is Ok: every non-blank line a row, its numeric cells the reference's bits, its text cells the cells. */
static void CheckRows(const CsvScanArguments *const a, const CsvScanResult *const result) {
    size_t row = 0;
    size_t line;
    size_t start = 0;
    size_t stop = 0;
    for (line = 0; line < result->line; line++) {
        size_t i;
        size_t k;
        int blank = 1;
        CHECK(NthLine(a->body, a->size, line, &start, &stop));
        for (i = start; i < stop; i++) {
            CHECK(CsvScanIsPlain(a->body[i]));
            blank = blank && (a->body[i] == ' ' || a->body[i] == '\t');
        }
        if (blank) {
            continue;
        }
        for (k = 0; k < a->numericCount; k++) {
            size_t first = 0;
            size_t last = 0;
            double expected = 0.0;
            const double got = a->numbers[k * a->capacity + row];
            CHECK(Cell(a->body, start, stop, (size_t)a->numeric[k], &first, &last));
            CHECK(ReferenceCell(a->body + first, last - first, &expected));
            CHECK(memcmp(&expected, &got, sizeof(double)) == 0);
        }
        for (k = 0; k < a->textCount; k++) {
            size_t first = 0;
            size_t last = 0;
            const int64_t index = a->textIndex[row * a->textCount + k];
            CHECK(Cell(a->body, start, stop, (size_t)a->text[k], &first, &last));
            CHECK(index >= 0 && (size_t)index < result->distinct[k]);
            CHECK((size_t)a->distinctLength[k * a->capacity + (size_t)index] == last - first);
            CHECK(memcmp(a->body + a->distinctStart[k * a->capacity + (size_t)index], a->body + first, last - first) == 0);
        }
        row++;
    }
    CHECK(row == result->rows);
    CHECK(!NthLine(a->body, a->size, result->line, &start, &stop)); /* every line was read */
}

/* A scan that stopped: on a line of the body, which the reference finds not plain there. */
static void CheckStop(const CsvScanArguments *const a, const CsvScanResult *const result, const CsvScanStatus status) {
    size_t start = 0;
    size_t stop = 0;
    CHECK(NthLine(a->body, a->size, result->line, &start, &stop));
    if (status == CsvScanNotNumber) {
        size_t first = 0;
        size_t last = 0;
        double value = 0.0;
        CHECK(Cell(a->body, start, stop, result->cell, &first, &last));
        CHECK(!ReferenceCell(a->body + first, last - first, &value));
    } else if (status == CsvScanNotPlainText) {
        size_t i;
        int plain = 1;
        for (i = start; i < stop; i++) {
            plain = plain && CsvScanIsPlain(a->body[i]);
        }
        CHECK(!plain);
    } else {
        CHECK(status == CsvScanRagged);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    int numeric[4];
    int text[4];
    size_t numericCount = 0;
    size_t textCount = 0;
    size_t capacity;
    size_t hashSize = 1;
    size_t k;
    const char *body;
    double *numbers;
    int64_t *work;
    if (size < 1) {
        return 0;
    }
    for (k = 0; k < 4; k++) { /* two bits per position: 0 skipped, 1 numeric, 2 text, 3 skipped */
        const int role = (data[0] >> (2 * k)) & 3;
        if (role == 1) {
            numeric[numericCount++] = (int)k;
        } else if (role == 2) {
            text[textCount++] = (int)k;
        }
    }
    body = (const char *)data + 1;
    size -= 1;
    capacity = CsvScanNewlines(body, size) + 1;
    while (hashSize < 2 * capacity) {
        hashSize *= 2;
    }
    numbers = (double *)malloc(capacity * (numericCount + 1) * sizeof(double));
    work = (int64_t *)malloc((3 * capacity + hashSize) * (textCount + 1) * sizeof(int64_t));
    CHECK(numbers != NULL && work != NULL);
    {
        /* each text column's row indices, distinct starts and lengths, hash slots: one block */
        const size_t block = capacity * (textCount + 1);
        const CsvScanArguments a = {body, size, numeric, numericCount, text, textCount, FUZZ_CSV_MISSING,
                                    sizeof(FUZZ_CSV_MISSING) - 1, capacity, numbers, work, work + block,
                                    work + 2 * block, work + 3 * block, hashSize, NULL}; /* NULL: strtod */
        CsvScanResult result;
        const CsvScanStatus status = CsvScan(&a, &result);
        CHECK(result.rows <= capacity);
        if (status == CsvScanOk) {
            CheckRows(&a, &result);
        } else {
            CheckStop(&a, &result, status);
        }
    }
    free(numbers);
    free(work);
    return 0;
}
