/* The array this firmware drives: the paper's palm array (assets/devices/palm-5x6.json). */
#ifndef TACTILE_CONFIG_H
#define TACTILE_CONFIG_H

#define ARRAY_NAME "palm-5x6"
#define ARRAY_COLS 5
#define ARRAY_ROWS 6
#define ARRAY_LEVELS 23 /* 0 = off .. 22 = full */
#define WATCHDOG_MS 250

#define F_TIMER 16000000UL
#define TIMER_PRESCALE 8                  /* Timer1 counts at 2 MHz: half microseconds */
#define TIMER_TICK 300                    /* a PWM slot: 300 counts, 150 us, 6666.7 a second */
#define PWM_SLOTS (ARRAY_LEVELS - 1)      /* 22 slots a period */
#define PWM_HZ 303                        /* 6666.7 / 22 = 303.03 */

/* Timed frames: the queue's head is built and armed once its time is less than ARM_WINDOW_US
 * away; compare match B is set for it no later than ARM_MARGIN_COUNTS (half microseconds)
 * before its time, else it plays at once. The match fires ONSET_LEAD_COUNTS early: from the
 * match to the write of PORTA the interrupt takes about 41 cycles (2.5 us: its entry, a few
 * register saves, the slot's row), counted on the machine code by
 * tests/test_firmware_schedule.py. */
#define ARM_WINDOW_US 16000
#define ARM_MARGIN_COUNTS 12
#define ONSET_LEAD_COUNTS 5

#define UART_UBRR 16 /* with U2X0: 16 MHz / 8 / 17 = 117,647 baud (115200 + 2.1 %) */

#endif
