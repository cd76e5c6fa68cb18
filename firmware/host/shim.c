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
static uint32_t now; /* the array's clock, microseconds */

void shim_reset(void)
{
    static const tp_config config = {ARRAY_COLS, ARRAY_ROWS, ARRAY_LEVELS, WATCHDOG_MS, PWM_HZ,
                                     ARRAY_NAME};
    tp_init(&state, &config);
    replies_len = 0;
    now = 0;
}

static void keep_reply(void)
{
    if (replies_len + state.reply_len <= sizeof replies) {
        memcpy(replies + replies_len, state.reply, state.reply_len);
        replies_len += state.reply_len;
    }
}

/* What main.c's loop does with the queue, without the timer: play the timed frames that are due
 * (late: due before they arrived). Returns how many played. */
static int play_due(uint8_t arriving)
{
    int played = 0;
    const tp_timed *head;
    while ((head = tp_head(&state)) != NULL && (int32_t)(head->at_us - now) <= 0) {
        tp_played(&state, arriving && (int32_t)(head->at_us - now) < 0);
        played++;
    }
    return played;
}

/* Feed one byte at the current time; 1 if a frame was applied (a frame for now, or a timed frame
 * whose time had come). */
int shim_feed(const uint8_t *data, size_t n)
{
    int applied = 0;
    for (size_t i = 0; i < n; i++) {
        int result = tp_feed(&state, data[i], now);
        if (result == TP_APPLIED)
            applied++;
        else if (result == TP_QUEUED)
            applied += play_due(1);
        else if (result == TP_REPLY)
            keep_reply();
        else if (result == TP_CLOCK_ASKED) {
            tp_clock_reply(&state, now);
            keep_reply();
        }
    }
    return applied;
}

/* Advance the clock by ms, play the timed frames that became due, run the watchdog; the number
 * of frames played. */
int shim_advance(uint32_t ms)
{
    now += ms * 1000u;
    int played = play_due(0);
    tp_watchdog(&state, now);
    return played;
}

void shim_levels(uint8_t *out) { memcpy(out, state.levels, state.channels); }

size_t shim_replies(uint8_t *out, size_t max)
{
    size_t n = replies_len < max ? replies_len : max;
    memcpy(out, replies, n);
    replies_len = 0;
    return n;
}

/* frames applied, dropped, watchdog trips, the drops by reason (6), late, full, queued. */
void shim_counters(uint32_t *out)
{
    out[0] = state.frames_applied;
    out[1] = state.dropped;
    out[2] = state.watchdog_trips;
    for (int i = 0; i < TP_DROP_REASONS; i++)
        out[3 + i] = state.dropped_by[i];
    out[3 + TP_DROP_REASONS] = state.late;
    out[4 + TP_DROP_REASONS] = state.full;
    out[5 + TP_DROP_REASONS] = state.q_count;
}

/* The last applied levels' sequence number. */
int shim_last_seq(void) { return state.last_seq; }

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
