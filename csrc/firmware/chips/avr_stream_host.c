/**
 * @file avr_stream_host.c
 * @brief Runs an AVR replay (avr_stream.c) under libsimavr and serves its
 * requests from the record and checkpoint streams written by avr_vectors.py.
 * Prints the AVR's UART text; exits with the AVR's exit status (the replay's
 * result), or 2 if the simulation crashes, runs out of a stream or exceeds
 * the cycle budget.
 *
 *   avr_stream_host MCU ELF RECORDS CHECKPOINTS
 */

#include <simavr/avr_uart.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>
#include <simavr/sim_irq.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    uint8_t *data;
    size_t size;
    size_t position;
} Stream;

static Stream streams[3];
static avr_irq_t *input;
static int xon = 1;
static uint8_t pending[512];
static size_t pendingCount;
static size_t pendingPosition;
static int request;        /* 0: text; else the stream being requested */
static int requestBytes;   /* size bytes received so far */
static unsigned requestSize;
static char line[256];
static size_t lineLength;
static int exitStatus = -1;
static int failed;

static void Flush(void) {
    while (xon && (pendingPosition < pendingCount)) {
        avr_raise_irq(input, pending[pendingPosition++]);
    }
}

static void Xon(struct avr_irq_t *irq, uint32_t value, void *param) {
    (void) irq, (void) value, (void) param;
    xon = 1;
    Flush();
}

static void Xoff(struct avr_irq_t *irq, uint32_t value, void *param) {
    (void) irq, (void) value, (void) param;
    xon = 0;
}

static void Output(struct avr_irq_t *irq, uint32_t value, void *param) {
    (void) irq, (void) param;
    const uint8_t byte = (uint8_t) value;
    if (request != 0) {
        requestSize |= (unsigned) byte << (8 * requestBytes);
        if (++requestBytes < 2) {
            return;
        }
        Stream *const stream = &streams[request];
        if ((stream->position + requestSize > stream->size) || (requestSize > sizeof(pending))) {
            fprintf(stderr, "stream %d: %u B requested at %zu of %zu\n", request, requestSize, stream->position, stream->size);
            failed = 1;
        } else {
            memcpy(pending, stream->data + stream->position, requestSize);
            stream->position += requestSize;
            pendingCount = requestSize;
            pendingPosition = 0;
            Flush();
        }
        request = 0;
        return;
    }
    if ((byte == 1u) || (byte == 2u)) {
        request = byte;
        requestBytes = 0;
        requestSize = 0;
        return;
    }
    if (byte == '\n') {
        line[lineLength] = '\0';
        printf("%s\n", line);
        fflush(stdout);
        if (strncmp(line, "exit ", 5) == 0) {
            exitStatus = atoi(line + 5);
        }
        lineLength = 0;
    } else if (lineLength + 1 < sizeof(line)) {
        line[lineLength++] = (char) byte;
    }
}

static void Load(Stream *const stream, const char *const path) {
    FILE *const file = fopen(path, "rb");
    if (file == NULL) {
        perror(path);
        exit(2);
    }
    fseek(file, 0, SEEK_END);
    stream->size = (size_t) ftell(file);
    fseek(file, 0, SEEK_SET);
    stream->data = malloc(stream->size + 1);
    if ((stream->data == NULL) || (fread(stream->data, 1, stream->size, file) != stream->size)) {
        fprintf(stderr, "%s: read failed\n", path);
        exit(2);
    }
    fclose(file);
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: %s MCU ELF RECORDS CHECKPOINTS\n", argv[0]);
        return 2;
    }
    Load(&streams[1], argv[3]);
    Load(&streams[2], argv[4]);
    elf_firmware_t firmware;
    memset(&firmware, 0, sizeof(firmware));
    if (elf_read_firmware(argv[2], &firmware) != 0) {
        fprintf(stderr, "%s: not an AVR ELF\n", argv[2]);
        return 2;
    }
    avr_t *const avr = avr_make_mcu_by_name(argv[1]);
    if (avr == NULL) {
        fprintf(stderr, "%s: unknown MCU\n", argv[1]);
        return 2;
    }
    avr_init(avr);
    avr->frequency = 16000000;
    avr_load_firmware(avr, &firmware);
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~(uint32_t) AVR_UART_FLAG_STDIO;
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    input = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), Output, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), Xon, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), Xoff, NULL);
    for (;;) {
        const int state = avr_run(avr);
        if ((state == cpu_Done) || (state == cpu_Crashed) || failed || (exitStatus >= 0)) {
            if (state == cpu_Crashed) {
                fprintf(stderr, "AVR crashed at cycle %llu\n", (unsigned long long) avr->cycle);
                return 2;
            }
            break;
        }
    }
    printf("avr cycles %llu, records sent %zu of %zu B, checkpoints %zu of %zu B\n", (unsigned long long) avr->cycle,
           streams[1].position, streams[1].size, streams[2].position, streams[2].size);
    return failed ? 2 : exitStatus;
}
