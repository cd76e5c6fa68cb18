/*
 * Software PWM tables: which pins are on in each slot of a PWM period.
 *
 * A period has `slots` slots (22 for 23 levels: level L is on for the first L slots, so level 0
 * is off, 22 full). table[slot * ports + port] holds the bits of that port that are on in that
 * slot. Portable C99: compiled for the firmware and for the host tests.
 */
#ifndef TACTILE_PWM_H
#define TACTILE_PWM_H

#include <stdint.h>

typedef struct {
    uint8_t port; /* index into the firmware's list of ports */
    uint8_t bit;  /* 0..7 */
} pwm_pin;

/* Fill table (slots * ports bytes) from channel levels; levels above `slots` count as full. */
void pwm_build(const uint8_t *levels, uint16_t channels, const pwm_pin *pins, uint8_t ports,
               uint8_t slots, uint8_t *table);

#endif
