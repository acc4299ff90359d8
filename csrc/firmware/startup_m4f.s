/*
 * startup_m4f.s: vector table and reset handler for bare-metal Cortex-M4F
 * programs run on QEMU -M mps2-an386 with -semihosting.
 *
 * The reset handler enables the FPU (CPACR 0xE000ED88, CP10 and CP11 full
 * access, bits 20-23) before any float instruction runs, then enters newlib's
 * rdimon start-up (_start: zeroes .bss, sets up semihosting stdio, calls
 * main, exits through semihosting with main's return value). Any fault exits
 * QEMU through semihosting with a run-time-error status instead of hanging.
 */

    .syntax unified
    .cpu cortex-m4
    .fpu fpv4-sp-d16
    .thumb

    .section .vectors, "a", %progbits
    .align 2
    .global vectorTable
vectorTable:
    .word __stack                   /* initial main stack pointer */
    .word ResetHandler
    .word FaultHandler              /* NMI */
    .word FaultHandler              /* HardFault */
    .word FaultHandler              /* MemManage */
    .word FaultHandler              /* BusFault */
    .word FaultHandler              /* UsageFault */
    .word 0, 0, 0, 0
    .word FaultHandler              /* SVCall */
    .word FaultHandler              /* DebugMonitor */
    .word 0
    .word FaultHandler              /* PendSV */
    .word FaultHandler              /* SysTick */

    .text
    .thumb_func
    .global ResetHandler
ResetHandler:
    ldr r0, =0xE000ED88             /* CPACR */
    ldr r1, [r0]
    orr r1, r1, #(0xF << 20)        /* CP10, CP11: full access */
    str r1, [r0]
    dsb
    isb
    b _start

    .thumb_func
    .global FaultHandler
FaultHandler:
    movs r0, #0x18                  /* SYS_EXIT */
    ldr r1, =0x20023                /* ADP_Stopped_RunTimeErrorUnknown: QEMU exits with status 1 */
    bkpt 0xAB
    b .
