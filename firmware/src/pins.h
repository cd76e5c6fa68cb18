/* The pin map: channel k (= row * 5 + col) -> port (0 PORTA, 1 PORTC, 2 PORTL, 3 PORTK), bit. */
#ifndef TACTILE_PINS_H
#define TACTILE_PINS_H

#include "pwm.h"

#define PIN_PORTS 4

static const pwm_pin PINS[30] = {
    {0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}, {0, 6}, {0, 7}, /* D22-D29 */
    {1, 0}, {1, 1}, {1, 2}, {1, 3}, {1, 4}, {1, 5}, {1, 6}, {1, 7}, /* D37-D30 */
    {2, 0}, {2, 1}, {2, 2}, {2, 3}, {2, 4}, {2, 5}, {2, 6}, {2, 7}, /* D49-D42 */
    {3, 0}, {3, 1}, {3, 2}, {3, 3}, {3, 4}, {3, 5},                 /* A8-A13 */
};

#endif
