/* The array this firmware drives: the paper's palm array (assets/devices/palm-5x6.json). */
#ifndef TACTILE_CONFIG_H
#define TACTILE_CONFIG_H

#define ARRAY_NAME "palm-5x6"
#define ARRAY_COLS 5
#define ARRAY_ROWS 6
#define ARRAY_LEVELS 23 /* 0 = off .. 22 = full */
#define WATCHDOG_MS 250

#define F_TIMER 16000000UL
#define TIMER_PRESCALE 8
#define TIMER_TOP 299 /* 16 MHz / 8 / 300 = 6666.7 ticks a second */
#define PWM_SLOTS (ARRAY_LEVELS - 1)      /* 22 slots a period */
#define PWM_HZ 303                        /* 6666.7 / 22 = 303.03 */
#define TICK_US_NUM 3                     /* one tick is 0.15 ms = 3 / 20 ms */
#define TICK_US_DEN 20

#define UART_UBRR 16 /* with U2X0: 16 MHz / 8 / 17 = 117,647 baud (115200 + 2.1 %) */

#endif
