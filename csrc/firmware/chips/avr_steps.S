/*
 * avr_steps.S: counts the CPU cycles of each call of the Sized...Update
 * function that cycles_<name>.c makes, on an AVR under simavr. Linked with
 * -Wl,--wrap=$(STEP_FUNCTION). The wrapper leaves the stack as the caller
 * built it (the INS's vectors travel on the stack): it pops its return
 * address into static memory, clears Timer1 and starts it at the CPU clock
 * (prescaler 1; avr_steps.c counts its overflows), calls the real function,
 * reads Timer1 (into chipTimerCount) and stops it, and passes the count to ChipStepsRecord (avr_steps.c),
 * keeping the function's result (r24:r25). Scratch registers: r26, r27 and
 * r30, r31 carry no argument. Devices with a 2-byte PC (up to 128 KB flash).
 */
#include <avr/io.h>

#define WRAP2(name) __wrap_##name
#define WRAP(name) WRAP2(name)
#define REAL2(name) __real_##name
#define REAL(name) REAL2(name)

    .section .bss
chipReturnAddress: .skip 2
chipResult: .skip 2
    .global chipTimerCount
chipTimerCount: .skip 2

    .text
    .global WRAP(STEP_FUNCTION)
    .type WRAP(STEP_FUNCTION), @function
WRAP(STEP_FUNCTION):
    pop r27
    pop r26
    sts chipReturnAddress, r26
    sts chipReturnAddress + 1, r27
    sts _SFR_MEM_ADDR(TCNT1H), r1
    sts _SFR_MEM_ADDR(TCNT1L), r1
    ldi r26, (1 << CS10)
    sts _SFR_MEM_ADDR(TCCR1B), r26
    call REAL(STEP_FUNCTION)
    lds r30, _SFR_MEM_ADDR(TCNT1L)
    lds r31, _SFR_MEM_ADDR(TCNT1H)
    sts _SFR_MEM_ADDR(TCCR1B), r1
    sts chipTimerCount, r30
    sts chipTimerCount + 1, r31
    sts chipResult, r24
    sts chipResult + 1, r25
    call ChipStepsRecord
    lds r24, chipResult
    lds r25, chipResult + 1
    lds r26, chipReturnAddress
    lds r27, chipReturnAddress + 1
    push r26
    push r27
    ret
    .size WRAP(STEP_FUNCTION), . - WRAP(STEP_FUNCTION)
