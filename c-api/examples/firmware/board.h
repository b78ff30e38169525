/* What startup.c gives main.c: semihosting output and exit. */
#ifndef BOARD_H
#define BOARD_H
#include <stdint.h>
void board_write(const char *s, uint32_t len);
void board_exit(int ok);
#endif
