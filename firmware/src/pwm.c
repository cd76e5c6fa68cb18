#include "pwm.h"

#include <string.h>

void pwm_build(const uint8_t *levels, uint16_t channels, const pwm_pin *pins, uint8_t ports,
               uint8_t slots, uint8_t *table)
{
    memset(table, 0, (uint16_t)slots * ports);
    for (uint16_t c = 0; c < channels; c++) {
        uint8_t on = levels[c] < slots ? levels[c] : slots;
        uint8_t mask = (uint8_t)(1u << pins[c].bit);
        uint8_t *cell = table + pins[c].port;
        for (uint8_t slot = 0; slot < on; slot++, cell += ports)
            *cell |= mask;
    }
}
