/*
 * The firmware's parser and PWM tables on the host, for the test suite (ctypes): the same
 * protocol.c and pwm.c as the ATmega2560 build, configured as the palm array.
 */
#include <string.h>

#include "config.h"
#include "pins.h"
#include "protocol.h"
#include "pwm.h"

static tp_state state;
static uint8_t replies[4096];
static size_t replies_len;
static uint32_t now;

void shim_reset(void)
{
    static const tp_config config = {ARRAY_COLS, ARRAY_ROWS, ARRAY_LEVELS, WATCHDOG_MS, PWM_HZ,
                                     ARRAY_NAME};
    tp_init(&state, &config);
    replies_len = 0;
    now = 0;
}

/* Feed bytes at the current time; returns how many frames were applied. */
int shim_feed(const uint8_t *data, size_t n)
{
    int applied = 0;
    for (size_t i = 0; i < n; i++) {
        int result = tp_feed(&state, data[i], now);
        if (result == TP_APPLIED)
            applied++;
        else if (result == TP_REPLY && replies_len + state.reply_len <= sizeof replies) {
            memcpy(replies + replies_len, state.reply, state.reply_len);
            replies_len += state.reply_len;
        }
    }
    return applied;
}

/* Advance the clock by ms and run the watchdog; 1 if it tripped. */
int shim_advance(uint32_t ms)
{
    now += ms;
    return tp_watchdog(&state, now);
}

void shim_levels(uint8_t *out) { memcpy(out, state.levels, state.channels); }

size_t shim_replies(uint8_t *out, size_t max)
{
    size_t n = replies_len < max ? replies_len : max;
    memcpy(out, replies, n);
    replies_len = 0;
    return n;
}

/* frames applied, dropped, watchdog trips, then the drops by reason (6). */
void shim_counters(uint32_t *out)
{
    out[0] = state.frames_applied;
    out[1] = state.dropped;
    out[2] = state.watchdog_trips;
    for (int i = 0; i < TP_DROP_REASONS; i++)
        out[3 + i] = state.dropped_by[i];
}

uint16_t shim_crc16(const uint8_t *data, size_t n) { return tp_crc16(data, n); }

size_t shim_cobs_encode(const uint8_t *in, size_t n, uint8_t *out)
{
    return tp_cobs_encode(in, n, out);
}

/* The PWM table of the firmware's pin map for the given levels (22 slots x 4 ports). */
void shim_pwm_table(const uint8_t *levels, uint8_t *table)
{
    pwm_build(levels, 30, PINS, PIN_PORTS, PWM_SLOTS, table);
}
