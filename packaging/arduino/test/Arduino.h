/**
 * @file Arduino.h
 * @brief A minimal stand-in for the Arduino core's Arduino.h: just what the
 * FusionAltitude example sketches use (millis, micros, Serial), so that the
 * sketches compile and link for an ATmega328P and a Cortex-M4F without an
 * Arduino installation (tests/test_arduino.py). Not part of the library.
 */

#ifndef ARDUINO_H_STAND_IN
#define ARDUINO_H_STAND_IN

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

unsigned long millis(void);
unsigned long micros(void);

/* The subset of Arduino's HardwareSerial (Print) the sketches call. */
class StandInSerial {
public:
    void begin(unsigned long baud);
    size_t print(const char *text);
    size_t print(long value);
    size_t print(int value);
    size_t println(void);
    size_t println(const char *text);
    size_t println(int value);
};

extern StandInSerial Serial;

void setup(void);
void loop(void);

#endif
