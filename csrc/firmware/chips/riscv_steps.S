/*
 * riscv_steps.S: counts the instructions of each call of the Sized...Update
 * function that cycles_<name>.c makes, on RV32 under QEMU -icount (minstret
 * counts retired instructions there). Linked with -Wl,--wrap=$(STEP_FUNCTION):
 * the calls of cycles_<name>.c reach __wrap_STEP_FUNCTION below, which reads
 * minstret around the real function and passes the difference (the call, the
 * function and its return) to ChipStepsRecord (riscv_steps.c). Every argument
 * of the Update functions travels in registers (ilp32/ilp32f), so the wrapper
 * may move the stack pointer.
 */
#define WRAP2(name) __wrap_##name
#define WRAP(name) WRAP2(name)
#define REAL2(name) __real_##name
#define REAL(name) REAL2(name)

    .text
    .globl WRAP(STEP_FUNCTION)
    .type WRAP(STEP_FUNCTION), @function
WRAP(STEP_FUNCTION):
    addi sp, sp, -16
    sw ra, 12(sp)
    sw s0, 8(sp)
    sw s1, 4(sp)
    .word 0xB0202473 /* csrr s0, minstret (encoded: rv32imac's assembler has no Zicsr) */
    call REAL(STEP_FUNCTION)
    .word 0xB02022F3 /* csrr t0, minstret */
    mv s1, a0
    sub a0, t0, s0
    call ChipStepsRecord
    mv a0, s1
    lw s1, 4(sp)
    lw s0, 8(sp)
    lw ra, 12(sp)
    addi sp, sp, 16
    ret
    .size WRAP(STEP_FUNCTION), . - WRAP(STEP_FUNCTION)
