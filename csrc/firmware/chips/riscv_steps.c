/**
 * @file riscv_steps.c
 * @brief Prints the instruction count of each wrapped Update call
 * (riscv_steps.S) as "step <n>: <count> instructions" over semihosting.
 */

#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>

void ChipStepsRecord(uint32_t instructions);

void ChipStepsRecord(const uint32_t instructions) {
    static uint32_t step;
    printf("step %" PRIu32 ": %" PRIu32 " instructions\n", step, instructions);
    step++;
}
