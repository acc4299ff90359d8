/**
 * @file avr_stream.c
 * @brief The AVR side of a streamed replay (avr_vectors.py, avr_stream_host.c):
 * stdout on USART0, the next record or the current checkpoint fetched from
 * the host on request, and the exit that ends the simulation.
 *
 * Request: one byte 0x01 (records) or 0x02 (checkpoints) and the size,
 * little-endian; the host answers with that many bytes of the stream. The
 * replay indexes the arrays in order (record i once, in iteration i;
 * checkpoint c until its record is passed), so each call returns the address
 * that the replay's index turns into the buffer: buffer - index * size,
 * computed on the AVR's 16-bit addresses (the replay's pointer arithmetic
 * then lands on the buffer; valid on avr-gcc, not portable C).
 */

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stdint.h>
#include <stdio.h>

#define RECORD_BYTES (96u)      /* the largest record: the observer's 75 B */
#define CHECKPOINT_BYTES (432u) /* the largest checkpoint: the INS's 420 B */

const void *AvrStreamRecords(uint16_t size, uint16_t count);
const void *AvrStreamCheckpoints(uint16_t size, uint16_t count);
void __wrap_exit(int status) __attribute__((noreturn));

static uint8_t record[RECORD_BYTES];
static uint8_t checkpoint[CHECKPOINT_BYTES];
static uint16_t recordsFetched;
static uint16_t checkpointsFetched;

static int UartPut(char character, FILE *stream) {
    (void) stream;
    while ((UCSR0A & (1 << UDRE0)) == 0) {
    }
    UDR0 = (uint8_t) character;
    return 0;
}

static uint8_t UartGet(void) {
    while ((UCSR0A & (1 << RXC0)) == 0) {
    }
    return UDR0;
}

static FILE uart = FDEV_SETUP_STREAM(UartPut, NULL, _FDEV_SETUP_WRITE);

/* Runs before main (avr-libc's .init8): USART0 at 1 Mbaud, both ways, as stdout. */
static void AvrStreamInit(void) __attribute__((naked, used, section(".init8")));
static void AvrStreamInit(void) {
    UBRR0 = 0;
    UCSR0B = (1 << TXEN0) | (1 << RXEN0);
    stdout = &uart;
}

static void Fetch(const uint8_t stream, uint8_t *const buffer, const uint16_t capacity, const uint16_t size) {
    if (size > capacity) {
        printf("stream %u: %u B does not fit %u B\n", stream, size, capacity);
        __wrap_exit(3);
    }
    (void) UartPut((char) stream, NULL);
    (void) UartPut((char) (size & 0xFFu), NULL);
    (void) UartPut((char) (size >> 8), NULL);
    for (uint16_t i = 0; i < size; i++) {
        buffer[i] = UartGet();
    }
}

const void *AvrStreamRecords(const uint16_t size, const uint16_t count) {
    (void) count;
    Fetch(1u, record, RECORD_BYTES, size);
    const uint16_t index = recordsFetched++;
    return (const void *) ((uintptr_t) record - (uintptr_t) index * size);
}

const void *AvrStreamCheckpoints(const uint16_t size, const uint16_t count) {
    /* the cached checkpoint is passed once the replay is beyond its record (its first field) */
    uint32_t cachedRecord;
    __builtin_memcpy(&cachedRecord, checkpoint, sizeof(cachedRecord));
    const uint16_t currentRecord = (uint16_t) (recordsFetched - 1u);
    if ((checkpointsFetched == 0u) || ((cachedRecord < currentRecord) && (checkpointsFetched < count))) {
        Fetch(2u, checkpoint, CHECKPOINT_BYTES, size);
        checkpointsFetched++;
    }
    return (const void *) ((uintptr_t) checkpoint - (uintptr_t) (checkpointsFetched - 1u) * size);
}

void __wrap_exit(int status) {
    printf("exit %d\n", status);
    while ((UCSR0A & (1 << UDRE0)) == 0) {
    }
    cli();
    sleep_enable();
    sleep_cpu();
    for (;;) {
    }
}
