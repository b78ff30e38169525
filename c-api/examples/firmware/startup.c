/* Minimal start-up for the mps2-an386 Cortex-M4F under QEMU: the vector table, the reset
 * handler (FPU on, .data copied, .bss zeroed, main, exit through semihosting), and the
 * semihosting calls the example uses (stdout, exit). No C library. */
#include <stdint.h>

#include "board.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
int main(void);

/* ARM semihosting: operation in r0, argument in r1, `bkpt 0xab` (QEMU with
 * -semihosting-config enable=on). */
static int32_t semihost(int32_t op, const void *arg) {
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

#define SYS_OPEN 0x01
#define SYS_WRITE 0x05
#define SYS_EXIT 0x18
#define ADP_STOPPED_APPLICATION_EXIT 0x20026
#define ADP_STOPPED_RUN_TIME_ERROR 0x20023

static int32_t stdout_handle = -1;

void board_write(const char *s, uint32_t len) {
    if (stdout_handle < 0) {
        /* ":tt" opened for writing ("w", mode 4) is the host's stdout. */
        const uint32_t open_args[3] = {(uint32_t)":tt", 4, 3};
        stdout_handle = semihost(SYS_OPEN, open_args);
    }
    const uint32_t write_args[3] = {(uint32_t)stdout_handle, (uint32_t)s, len};
    semihost(SYS_WRITE, write_args);
}

void board_exit(int ok) {
    semihost(SYS_EXIT,
             (const void *)(uintptr_t)(ok ? ADP_STOPPED_APPLICATION_EXIT : ADP_STOPPED_RUN_TIME_ERROR));
    for (;;) {
    }
}

void reset_handler(void) {
    /* CPACR: full access to CP10/CP11 (the FPU) before any floating-point instruction. */
    *(volatile uint32_t *)0xE000ED88 |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    for (uint32_t *s = &_sidata, *d = &_sdata; d < &_edata;) {
        *d++ = *s++;
    }
    for (uint32_t *d = &_sbss; d < &_ebss;) {
        *d++ = 0;
    }
    board_exit(main() == 0);
}

static void fault_handler(void) {
    board_write("fault\n", 6);
    board_exit(0);
}

__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
    &_estack, reset_handler, fault_handler, fault_handler, fault_handler, fault_handler,
    fault_handler, 0, 0, 0, 0, fault_handler, fault_handler, 0, fault_handler, fault_handler,
};
