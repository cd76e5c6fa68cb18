/*
 * Reference firmware of the palm array: an Arduino Mega 2560 (ATmega2560, 16 MHz) receives wire
 * format 2 on UART0 at 115200 baud and drives 30 vibration motors by software PWM at 303 Hz with
 * 23 levels. Plain C with avr-libc; no Arduino core.
 *
 * - Timer1 counts at 2 MHz (clk / 8) from 0 to 299 (CTC), a PWM slot of 150 us: compare match A
 *   at the end of each slot (6666.7 Hz) counts the slots and steps through the 22 slots of a
 *   PWM period, writing four ports from a precomputed table (pwm.c). The slot count and the
 *   counter are the array's clock: microseconds = slots * 150 + counter / 2, wrapping at 2^32
 *   (71.6 minutes; clock_us). A frame for now (type 'F') waits for the end of the period: a
 *   period never mixes two frames (three tables: playing, waiting, being built).
 * - Compare match B plays a timed frame (type 'T') at its time: the moment the counter reaches
 *   the frame's time in the frame's slot, its table takes over, from the slot the period is in
 *   (the period runs on undisturbed, so every duty stays level / 22 on average; only the period
 *   the frame starts in mixes the two frames, at the frame's time). The frame's table is built
 *   ahead of time into a fourth table and armed for its slot; compare match A sets the match
 *   when that slot begins. A frame whose time has passed plays at once, counted late.
 * - UART0 receive and transmit run from interrupts through ring buffers; the receive interrupt
 *   stamps every message delimiter with the clock (the clock exchange's arrival time). The main
 *   loop feeds received bytes to the parser (protocol.c) and sleeps when there is nothing to do.
 * - The watchdog turns every motor off at once when more than 250 ms have passed since the last
 *   valid frame, and drops the timed frames still waiting.
 *
 * Pin map (channel = row * 5 + col, row 0 at the bottom): channels 0-7 on PORTA (D22-D29),
 * 8-15 on PORTC (D37-D30), 16-23 on PORTL (D49-D42), 24-29 on PORTK bits 0-5 (A8-A13).
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <util/atomic.h>

#include "config.h"
#include "pins.h"
#include "protocol.h"
#include "pwm.h"

#define CHANNELS (ARRAY_COLS * ARRAY_ROWS)
#define PORTS PIN_PORTS
#define NONE 0xFF
/* A compare value past TOP: compare match B never happens, so its flag is never set while no
 * frame is armed, and arming needs no write to TIFR1. (Clearing OCF1B by writing TIFR1 would do
 * on the ATmega2560, but simavr 1.6 clears every pending timer flag on such a write, a pending
 * compare match A included: the slot was then never counted, and the clock fell behind.) */
#define NEVER 0xFFFF

/* Four tables: the one the timer plays, one waiting for the next period (a frame for now), one
 * holding the next timed frame (armed on compare match B), one being built. */
static uint8_t tables[4][PWM_SLOTS * PORTS];
static volatile uint8_t playing = 0, waiting = NONE, armed = NONE;
static volatile uint8_t slot = PWM_SLOTS - 1; /* the slot being played */
static volatile uint32_t ticks;        /* slots since the timer started: 150 us each */
static volatile uint8_t onset;         /* compare match B played the armed frame */
static const uint8_t *volatile armed_table; /* tables[armed], for compare match B */
static volatile uint32_t armed_tick;   /* the slot the armed frame plays in ... */
static volatile uint16_t armed_counts; /* ... and where in it (counts, 0..299) */
static uint8_t built = NONE;           /* the table holding the queue's head, if built */

static volatile uint8_t rx_buf[256], tx_buf[128];
static volatile uint8_t rx_head, rx_tail, tx_head, tx_tail;
#define STAMPS 32 /* arrival times of the delimiters waiting in rx_buf: counter, slot count */
static volatile uint16_t stamp_counts[STAMPS];
static volatile uint32_t stamp_ticks[STAMPS];
static volatile uint8_t stamp_head, stamp_tail;

/* The slot count and the counter now; call with interrupts off. A slot that ended but has not
 * been counted yet (its compare flag is set and the counter restarted) is counted here. */
static uint32_t ticks_at(uint16_t *counts_out)
{
    uint16_t counts = TCNT1;
    uint32_t t = ticks;
    if ((TIFR1 & _BV(OCF1A)) && counts < TIMER_TICK / 2)
        t++;
    *counts_out = counts;
    return t;
}

static uint32_t clock_us(void)
{
    uint16_t counts;
    uint32_t t;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { t = ticks_at(&counts); }
    return t * (TIMER_TICK / 2) + (counts >> 1);
}

/* The armed table takes over in the slot being played. Interrupts are off (compare match B, or
 * the caller); the ports first, so that the pins change a fixed number of cycles after the
 * match (the interrupt's entry and a few register saves), then the bookkeeping. */
static inline __attribute__((always_inline)) void play_armed(void)
{
    const uint8_t *row = armed_table + slot * PORTS;
    PORTA = row[0];
    PORTC = row[1];
    PORTL = row[2];
    PORTK = row[3];
    playing = armed;
    armed = NONE;
    waiting = NONE;
    TIMSK1 &= (uint8_t)~_BV(OCIE1B);
    OCR1B = NEVER; /* no match, so no stale flag, until the next frame is armed */
    onset = 1;
}

ISR(TIMER1_COMPA_vect)
{
    ticks++;
    if (++slot == PWM_SLOTS) {
        slot = 0;
        if (waiting != NONE) { /* only between periods: a period never mixes two frames */
            playing = waiting;
            waiting = NONE;
        }
    }
    const uint8_t *row = tables[playing] + slot * PORTS;
    PORTA = row[0];
    PORTC = row[1];
    PORTL = row[2];
    PORTK = row[3];
    if (armed != NONE && ticks == armed_tick) { /* the armed frame plays in this slot */
        if (armed_counts > TCNT1 + ARM_MARGIN_COUNTS) {
            OCR1B = armed_counts;
            TIMSK1 |= _BV(OCIE1B);
        } else {
            play_armed(); /* at the slot's very start: now */
        }
    }
}

ISR(TIMER1_COMPB_vect) { play_armed(); }

/* Receive: the counter first (the delimiter's arrival, a fixed number of cycles after it), then
 * interrupts back on, so that a timed frame's compare match never waits for the rest. */
ISR(USART0_RX_vect)
{
    uint16_t counts = TCNT1;
    uint8_t byte = UDR0;
    uint32_t t = ticks;
    if ((TIFR1 & _BV(OCF1A)) && counts < TIMER_TICK / 2)
        t++;
    sei();
    uint8_t next = (uint8_t)(rx_head + 1);
    if (next == rx_tail)
        return; /* a full buffer drops the byte; the CRC then drops its message */
    if (byte == 0) {
        uint8_t at = stamp_head % STAMPS;
        if ((uint8_t)(stamp_head - stamp_tail) == STAMPS)
            return; /* no room for its arrival time: dropped like any byte of a full buffer */
        stamp_counts[at] = counts;
        stamp_ticks[at] = t;
        stamp_head++;
    }
    rx_buf[rx_head] = byte;
    rx_head = next;
}

/* The arrival time of the oldest delimiter waiting, on the microsecond clock. */
static uint32_t pop_stamp(void)
{
    uint8_t at = stamp_tail % STAMPS;
    stamp_tail++;
    return stamp_ticks[at] * (TIMER_TICK / 2) + (stamp_counts[at] >> 1);
}

ISR(USART0_UDRE_vect)
{
    if (tx_tail == tx_head) {
        UCSR0B &= (uint8_t)~_BV(UDRIE0);
        return;
    }
    UDR0 = tx_buf[tx_tail];
    tx_tail = (uint8_t)((tx_tail + 1) & 127);
}

static void send(const uint8_t *data, uint8_t n)
{
    for (uint8_t i = 0; i < n; i++) {
        uint8_t next = (uint8_t)((tx_head + 1) & 127);
        while (next == tx_tail) {
        } /* full: the interrupt drains it */
        tx_buf[tx_head] = data[i];
        tx_head = next;
        UCSR0B |= _BV(UDRIE0);
    }
}

static uint8_t free_table(void)
{
    uint8_t t = 0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        while (t == playing || t == waiting || t == armed || t == built)
            t++;
    }
    return t;
}

/* A frame for now: drop what is scheduled, play it from the next period. */
static void show(const uint8_t *levels)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        TIMSK1 &= (uint8_t)~_BV(OCIE1B);
        OCR1B = NEVER;
        armed = NONE;
    }
    built = NONE;
    uint8_t t = free_table();
    /* The timer may start playing the waiting table meanwhile; this one stays free. */
    pwm_build(levels, CHANNELS, PINS, PORTS, PWM_SLOTS, tables[t]);
    waiting = t;
}

/* The queue's head: build its table ahead, arm compare match B once its time is near, or play
 * it at once when its time has passed. One frame is armed at a time. */
static void schedule(tp_state *state)
{
    uint8_t played, busy;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        played = onset;
        onset = 0;
    }
    if (played) { /* the armed frame started: off the queue */
        built = NONE;
        tp_played(state, 0);
    }
    const tp_timed *head = tp_head(state);
    if (head == NULL)
        return;
    /* Armed, or played by an interrupt since the check above (then the next call pops it): a
     * frame is never armed twice. */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { busy = armed != NONE || onset; }
    if (busy)
        return;
    if ((int32_t)(head->at_us - clock_us()) > ARM_WINDOW_US)
        return;
    if (built == NONE) {
        uint8_t t = free_table();
        pwm_build(head->levels, CHANNELS, PINS, PORTS, PWM_SLOTS, tables[t]);
        built = t;
    }
    /* Where the frame's time falls: its slot and the count within it. The divisions take
     * hundreds of cycles, so they are done here, against a slot read just before, and not
     * between reading the counter and setting the compare. */
    uint16_t counts;
    uint32_t tick0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { tick0 = ticks_at(&counts); }
    int32_t ahead = (int32_t)(head->at_us - tick0 * (TIMER_TICK / 2)); /* from slot tick0 */
    int32_t q = ahead / (TIMER_TICK / 2), r = ahead - q * (TIMER_TICK / 2);
    if (r < 0) { /* floor division: a time in an earlier slot */
        q--;
        r += TIMER_TICK / 2;
    }
    uint32_t at_tick = tick0 + (uint32_t)q;
    uint16_t at_counts = (uint16_t)(2 * r);
    uint16_t lead_counts = at_counts > ONSET_LEAD_COUNTS ? at_counts - ONSET_LEAD_COUNTS : 0;
    uint8_t at_once = 0, late = 0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        uint32_t now_tick = ticks_at(&counts);
        int32_t slots = (int32_t)(at_tick - now_tick);
        armed = built;
        armed_table = tables[built];
        if (slots > 0) { /* a later slot: compare match A arms it there */
            armed_tick = at_tick;
            armed_counts = lead_counts;
        } else if (slots == 0 && lead_counts > counts + ARM_MARGIN_COUNTS) {
            OCR1B = lead_counts; /* later in this slot */
            TIMSK1 |= _BV(OCIE1B);
            armed_tick = now_tick - 1; /* compare match A leaves it alone */
        } else { /* due now, or past: play at once */
            play_armed();
            onset = 0;
            at_once = 1;
            late = slots < 0 || at_counts < counts;
        }
    }
    if (at_once) {
        built = NONE;
        tp_played(state, late);
    }
}

/* The watchdog: everything off now, not at the end of the period. */
static void all_off_now(void)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        for (uint8_t i = 0; i < sizeof tables[0]; i++)
            tables[playing][i] = 0;
        waiting = NONE;
        armed = NONE;
        TIMSK1 &= (uint8_t)~_BV(OCIE1B);
        OCR1B = NEVER;
        PORTA = PORTC = PORTL = PORTK = 0;
    }
    built = NONE;
}

int main(void)
{
    DDRA = 0xFF;
    DDRC = 0xFF;
    DDRL = 0xFF;
    DDRK = 0x3F;
    PORTA = PORTC = PORTL = PORTK = 0; /* all off before anything else */

    UCSR0A = _BV(U2X0); /* before UBRR0: simavr computes the baud rate when UBRR0 is written */
    UBRR0 = UART_UBRR;
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00); /* 8N1 */
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);

    TCCR1A = 0;
    OCR1A = TIMER_TICK - 1; /* CTC: 300 counts a slot */
    OCR1B = NEVER;
    TIMSK1 = _BV(OCIE1A);
    TCCR1B = _BV(WGM12) | _BV(CS11); /* CTC, clk / 8: the clock starts here */

    static tp_state state;
    static const tp_config config = {ARRAY_COLS, ARRAY_ROWS, ARRAY_LEVELS, WATCHDOG_MS, PWM_HZ,
                                     ARRAY_NAME};
    tp_init(&state, &config);
    set_sleep_mode(SLEEP_MODE_IDLE);
    sei();

    for (;;) {
        while (rx_tail != rx_head) {
            uint8_t byte = rx_buf[rx_tail];
            uint32_t at;
            if (byte == 0) {
                at = pop_stamp();
            } else {
                at = clock_us();
            }
            rx_tail = (uint8_t)(rx_tail + 1);
            int result = tp_feed(&state, byte, at);
            if (result == TP_APPLIED) {
                show(state.levels);
            } else if (result == TP_REPLY) {
                send(state.reply, state.reply_len);
            } else if (result == TP_CLOCK_ASKED) {
                tp_clock_reply(&state, clock_us());
                send(state.reply, state.reply_len);
            }
            schedule(&state); /* a due frame is not held up by a long run of bytes */
        }
        schedule(&state);
        if (tp_watchdog(&state, clock_us()))
            all_off_now();
        cli();
        if (rx_tail == rx_head && !onset) { /* nothing to do until the next interrupt */
            sleep_enable();
            sei();
            sleep_cpu();
            sleep_disable();
        }
        sei();
    }
}
