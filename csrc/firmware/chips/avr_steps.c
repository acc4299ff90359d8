/**
 * @file avr_steps.c
 * @brief The AVR side of avr_steps.S: Timer1's overflow count, the report of
 * each wrapped call as "step <n>: <count> cycles" on USART0 (simavr prints
 * it), and the exit that ends the simulation (interrupts off, then sleep).
 * The count includes the wrapper's call instruction, the Timer1 start and
 * read, and one overflow interrupt per 65536 cycles (about 0.1 %).
 */

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stdint.h>
#include <stdio.h>

void ChipStepsRecord(void);
void __wrap_exit(int status) __attribute__((noreturn));

static volatile uint16_t overflows;
extern volatile uint16_t chipTimerCount; /* Timer1 as the call returned (avr_steps.S) */

ISR(TIMER1_OVF_vect) {
    overflows++;
}

static int UartPut(char character, FILE *stream) {
    (void) stream;
    while ((UCSR0A & (1 << UDRE0)) == 0) {
    }
    UDR0 = (uint8_t) character;
    return 0;
}

static FILE uart = FDEV_SETUP_STREAM(UartPut, NULL, _FDEV_SETUP_WRITE);

/* Runs before main (avr-libc's .init8): the UART as stdout, Timer1 stopped with its overflow interrupt on. */
static void ChipStepsInit(void) __attribute__((naked, used, section(".init8")));
static void ChipStepsInit(void) {
    UCSR0B = (1 << TXEN0);
    stdout = &uart;
    TCCR1A = 0;
    TCCR1B = 0;
    TIMSK1 = (1 << TOIE1);
    sei();
}

void ChipStepsRecord(void) {
    static uint16_t step;
    const uint32_t cycles = ((uint32_t) overflows << 16) | chipTimerCount;
    overflows = 0;
    printf("step %u: %lu cycles\n", step, (unsigned long) cycles);
    step++;
}

void __wrap_exit(int status) {
    printf("exit %d\n", status);
    while ((UCSR0A & (1 << TXC0)) == 0 && (UCSR0A & (1 << UDRE0)) == 0) {
    }
    cli();
    sleep_enable();
    sleep_cpu();
    for (;;) {
    }
}
