/**
 * @file arduino_main.cpp
 * @brief The stand-in core behind Arduino.h: a 1 ms tick counter for millis
 * and micros, a Serial that writes into a volatile sink, and main() calling
 * setup() once and loop() a bounded number of times (so a simulator run ends).
 */

#include "Arduino.h"

static volatile unsigned long ticks; /* advanced by every call: a stand-in clock, 1 ms per call */
static volatile char sink;

unsigned long millis(void) {
    ticks = ticks + 1UL;
    return ticks;
}

unsigned long micros(void) {
    return millis() * 1000UL;
}

StandInSerial Serial;

void StandInSerial::begin(unsigned long baud) {
    sink = (char) (baud & 0xFFUL);
}

size_t StandInSerial::print(const char *text) {
    size_t count = 0;
    while (text[count] != '\0') {
        sink = text[count];
        count++;
    }
    return count;
}

size_t StandInSerial::print(long value) {
    char digits[12];
    size_t count = 0;
    unsigned long magnitude = (value < 0L) ? (0UL - (unsigned long) value) : (unsigned long) value;
    do {
        digits[count++] = (char) ('0' + (char) (magnitude % 10UL));
        magnitude /= 10UL;
    } while (magnitude != 0UL);
    size_t written = 0;
    if (value < 0L) {
        sink = '-';
        written++;
    }
    while (count > 0U) {
        sink = digits[--count];
        written++;
    }
    return written;
}

size_t StandInSerial::print(int value) {
    return print((long) value);
}

size_t StandInSerial::println(void) {
    sink = '\n';
    return 1U;
}

size_t StandInSerial::println(const char *text) {
    return print(text) + println();
}

size_t StandInSerial::println(int value) {
    return print(value) + println();
}

int main(void) {
    setup();
    for (int i = 0; i < 1000; i++) {
        loop();
    }
    return 0;
}
